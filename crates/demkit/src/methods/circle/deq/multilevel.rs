//! Coarse to fine: a large surface is first mapped through a coarse copy of itself, and the
//! fine map starts where the coarse one ended.
//!
//! The coarse surface is built in the initial map, where the surface is a planar
//! triangulation: every loop vertex and an evenly spread subset of the others (no two within
//! a few edges of each other on the surface), joined by the constrained Delaunay
//! triangulation of their initial positions with the loops as constraints. It spans exactly
//! the domain the fine surface spans (the loops are the same polygons), so every fine vertex
//! lies in one coarse triangle, with barycentric coordinates there. A coarse triangle's
//! population is the population of the fine faces it covers, its shape on the surface the
//! flat triangle through its corners.
//!
//! The coarse DEQ map moves every coarse triangle affinely; each fine vertex follows its
//! coarse triangle with its barycentric coordinates ([`Coarse::prolong`]). Inside one coarse
//! triangle nothing can fold; the few fine triangles that straddle coarse edges where the
//! coarse map bends sharply and fold are untangled ([`super::untangle`]). The fine map then
//! needs only local work: Newton's method around the faces whose density is still far off
//! (the `local_repair` of the method's driver), then a few iterations on the whole surface.

use super::layout::Layout;
use super::untangle::untangle_within_loops;
use crate::geometry::locate::PlanarLocator;
use crate::geometry::{count_nonpositive, face_areas};
use crate::mesh::topology::{topology, vertex_neighbours};
use crate::mesh::triangulate::{constrained_delaunay, faces_inside};
use crate::{Result, TriMesh};

/// Surfaces with at least this many faces are mapped coarse first (below it the direct
/// iteration takes a few seconds).
pub(crate) const MIN_FACES: usize = 40_000;

/// The coarse surface keeps about this many vertices.
const COARSE_VERTICES: usize = 4_000;

/// A coarse copy of a surface with holes, and where each fine vertex lies in it.
pub(crate) struct Coarse {
    /// The coarse surface: its vertices are fine vertices (same positions), its faces the
    /// Delaunay triangles of their initial map.
    pub mesh: TriMesh,
    /// The population of every coarse face.
    pub population: Vec<f64>,
    /// The loops in the coarse numbering, the outer one first.
    pub loops: Vec<Vec<u32>>,
    /// The initial map of the coarse vertices (where the fine initial map has them).
    pub initial: Vec<[f64; 3]>,
    /// Every fine vertex's coarse triangle (coarse numbering) and barycentric coordinates.
    location: Vec<([u32; 3], [f64; 3])>,
}

impl Coarse {
    /// The coarse copy of `mesh` (with `population` per face and boundary `loops`, the outer
    /// one first) built in its bijective initial map `x`; `keep` are vertices that must be
    /// coarse vertices too (landmarks). `None` when the coarse triangulation is not a surface
    /// with the same loops, or has a flat triangle on the surface.
    pub fn build(
        mesh: &TriMesh,
        population: &[f64],
        loops: &[Vec<u32>],
        keep: &[u32],
        x: &[[f64; 3]],
    ) -> Result<Option<Self>> {
        let n = mesh.n_vertices();
        let neighbours = vertex_neighbours(n, &mesh.faces);
        let mut must = vec![false; n];
        for &v in loops.iter().flatten().chain(keep) {
            must[v as usize] = true;
        }
        let chosen = select(&neighbours, &must, COARSE_VERTICES);
        let mut coarse_of = vec![u32::MAX; n];
        for (c, &v) in chosen.iter().enumerate() {
            coarse_of[v as usize] = c as u32;
        }
        let points: Vec<[f64; 2]> = chosen
            .iter()
            .map(|&v| [x[v as usize][0], x[v as usize][1]])
            .collect();
        let coarse_loops: Vec<Vec<u32>> = loops
            .iter()
            .map(|lp| lp.iter().map(|&v| coarse_of[v as usize]).collect())
            .collect();
        let segments: Vec<[usize; 2]> = coarse_loops
            .iter()
            .flat_map(|lp| {
                (0..lp.len()).map(move |k| [lp[k] as usize, lp[(k + 1) % lp.len()] as usize])
            })
            .collect();
        let Ok(cdt) = constrained_delaunay(&points, &segments) else {
            return Ok(None);
        };
        let polygons: Vec<Vec<usize>> = coarse_loops
            .iter()
            .map(|lp| lp.iter().map(|&v| v as usize).collect())
            .collect();
        let faces = faces_inside(&cdt.points, &cdt.faces, &polygons);
        let positions: Vec<[f64; 3]> = chosen.iter().map(|&v| mesh.positions[v as usize]).collect();
        let initial: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let coarse_mesh = TriMesh::new(positions, faces);
        // The same surface: one piece, genus 0, the same loops, every vertex used, and no
        // triangle flat on the surface.
        let topo = topology(&coarse_mesh);
        let mut used = vec![false; chosen.len()];
        for &v in coarse_mesh.faces.iter().flatten() {
            used[v as usize] = true;
        }
        let areas = face_areas(&coarse_mesh.positions, &coarse_mesh.faces);
        let largest = areas.iter().copied().fold(0.0, f64::max);
        if topo.components != 1
            || topo.genus != 0
            || topo.boundary_loops.len() != loops.len()
            || used.iter().any(|u| !u)
            || areas.iter().any(|&a| !(a > 1e-12 * largest))
            || count_nonpositive(&initial, &coarse_mesh.faces) > 0
        {
            return Ok(None);
        }
        // Where every fine vertex lies, and the coarse population.
        let locator = PlanarLocator::new(&initial, &coarse_mesh.faces);
        let mut location = Vec::with_capacity(n);
        for (v, p) in x.iter().enumerate().take(n) {
            let c = coarse_of[v];
            if c != u32::MAX {
                location.push(([c, c, c], [1.0, 0.0, 0.0]));
                continue;
            }
            let Some(at) = locator.locate([p[0], p[1]]) else {
                return Ok(None);
            };
            location.push((coarse_mesh.faces[at.face], at.weights));
        }
        let Some(coarse_population) =
            aggregate(mesh, population, x, &locator, &initial, &coarse_mesh.faces)
        else {
            return Ok(None);
        };
        Ok(Some(Self {
            mesh: coarse_mesh,
            population: coarse_population,
            loops: coarse_loops,
            initial,
            location,
        }))
    }

    /// The fine map in which every fine vertex follows its coarse triangle in the coarse map
    /// `g`, with the barycentric coordinates it has there in the initial map.
    fn follow(&self, g: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.location
            .iter()
            .map(|(corners, w)| {
                let mut p = [0.0; 3];
                for k in 0..3 {
                    let q = g[corners[k] as usize];
                    p[0] += w[k] * q[0];
                    p[1] += w[k] * q[1];
                }
                p
            })
            .collect()
    }

    /// The fine surface `mesh` (population `population`, loops `layout`) carried into the
    /// circle domain by the coarse map `g`: every fine vertex follows its coarse triangle
    /// ([`Self::follow`]), so the loops stay on their circles. A few fine triangles, where the
    /// coarse map bends sharply from one coarse triangle to the next, may fold; they are
    /// untangled ([`untangle`]) with the loops held, moving vertices a few rings around them
    /// (more if that is not enough). `None` when they cannot be.
    pub fn prolong(
        &self,
        g: &[[f64; 3]],
        mesh: &TriMesh,
        population: &[f64],
        layout: &Layout,
    ) -> Result<Option<Vec<[f64; 3]>>> {
        let mut y = self.follow(g);
        if count_nonpositive(&y, &mesh.faces) == 0 {
            return Ok(Some(y));
        }
        let untangled = untangle_within_loops(mesh, population, layout, &mut y, &UNTANGLE_RINGS)?;
        Ok(untangled.then_some(y))
    }
}

/// How far around folded triangles the untangling moves vertices, in rings, tried in turn. A
/// prolongation that cannot be untangled sends the whole surface to the direct map, which costs
/// far more than a wide untangling (`docs/deviations.md`, coarse-to-fine).
const UNTANGLE_RINGS: [usize; 5] = [2, 4, 8, 16, 32];

/// An evenly spread subset of the vertices: the `must` ones, then greedily every vertex more
/// than `r` edges from all chosen ones, with the smallest `r` that leaves at most `target`
/// (or `r = 6`). The chosen vertices in increasing order.
fn select(neighbours: &[Vec<u32>], must: &[bool], target: usize) -> Vec<u32> {
    let n = neighbours.len();
    let mut best = Vec::new();
    for r in 1..=6 {
        let mut distance = vec![u32::MAX; n];
        let mut chosen = vec![false; n];
        let mut queue = std::collections::VecDeque::new();
        // Cover the ring of radius r around `v` (distances only shrink).
        let cover =
            |v: usize, distance: &mut [u32], queue: &mut std::collections::VecDeque<usize>| {
                distance[v] = 0;
                queue.push_back(v);
                while let Some(u) = queue.pop_front() {
                    if distance[u] >= r {
                        continue;
                    }
                    for &w in &neighbours[u] {
                        let w = w as usize;
                        if distance[w] > distance[u] + 1 {
                            distance[w] = distance[u] + 1;
                            queue.push_back(w);
                        }
                    }
                }
            };
        for v in (0..n).filter(|&v| must[v]) {
            chosen[v] = true;
            cover(v, &mut distance, &mut queue);
        }
        for v in 0..n {
            if distance[v] == u32::MAX {
                chosen[v] = true;
                cover(v, &mut distance, &mut queue);
            }
        }
        best = (0..n as u32).filter(|&v| chosen[v as usize]).collect();
        if best.len() <= target {
            break;
        }
    }
    best
}

/// The population of every coarse face: each fine face's population split evenly over the
/// centroids of its four midpoint sub-triangles, each added to the coarse face containing it
/// in the initial map `x`. A coarse face that gets none (a sliver between sample points) gets
/// the fine density at its centroid times its initial area. `None` when a sample lies in no
/// coarse face.
fn aggregate(
    mesh: &TriMesh,
    population: &[f64],
    x: &[[f64; 3]],
    locator: &PlanarLocator,
    coarse_initial: &[[f64; 3]],
    coarse_faces: &[[u32; 3]],
) -> Option<Vec<f64>> {
    let mut out = vec![0.0; coarse_faces.len()];
    for (f, &p) in mesh.faces.iter().zip(population) {
        let [a, b, c] = f.map(|v| [x[v as usize][0], x[v as usize][1]]);
        let centroid = |u: [f64; 2], v: [f64; 2], w: [f64; 2]| {
            [(u[0] + v[0] + w[0]) / 3.0, (u[1] + v[1] + w[1]) / 3.0]
        };
        let mid = |u: [f64; 2], v: [f64; 2]| [0.5 * (u[0] + v[0]), 0.5 * (u[1] + v[1])];
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        for q in [
            centroid(a, ab, ca),
            centroid(ab, b, bc),
            centroid(ca, bc, c),
            centroid(ab, bc, ca),
        ] {
            out[locator.locate(q)?.face] += 0.25 * p;
        }
    }
    if out.iter().all(|&p| p > 0.0) {
        return Some(out);
    }
    // Fine density (population per initial area) at the empty faces' centroids.
    let fine = PlanarLocator::new(x, &mesh.faces);
    let fine_areas = face_areas(x, &mesh.faces);
    for (c, f) in coarse_faces.iter().enumerate() {
        if out[c] > 0.0 {
            continue;
        }
        let corners = f.map(|v| coarse_initial[v as usize]);
        let q = [
            (corners[0][0] + corners[1][0] + corners[2][0]) / 3.0,
            (corners[0][1] + corners[1][1] + corners[2][1]) / 3.0,
        ];
        let at = fine.locate(q)?;
        let area = 0.5
            * ((corners[1][0] - corners[0][0]) * (corners[2][1] - corners[0][1])
                - (corners[2][0] - corners[0][0]) * (corners[1][1] - corners[0][1]));
        out[c] = population[at.face] / fine_areas[at.face] * area;
        if !(out[c] > 0.0 && out[c].is_finite()) {
            return None;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::disk_with_holes;
    use crate::init::circle_domain::ordered_loops;

    /// A disk with two holes (a few thousand vertices), its population, its loops (outer
    /// first) and its initial map.
    type Disk = (TriMesh, Vec<f64>, Vec<Vec<u32>>, Vec<[f64; 3]>);
    fn disk() -> Disk {
        let mesh = disk_with_holes(&[(0.4, 0.1, 0.2), (-0.35, -0.2, 0.15)], 60).unwrap();
        let population: Vec<f64> = face_areas(&mesh.positions, &mesh.faces)
            .iter()
            .zip(&mesh.faces)
            .map(|(a, f)| a * (1.0 + 3.0 * (mesh.positions[f[0] as usize][0] > 0.0) as u8 as f64))
            .collect();
        let loops = ordered_loops(&mesh, &topology(&mesh).boundary_loops).unwrap();
        let layout = Layout::new(&mesh, &loops);
        let x = super::super::initial::initial_map(&mesh, &population, &layout).unwrap();
        (mesh, population, loops, x)
    }

    #[test]
    fn the_coarse_copy_spans_the_same_domain_and_carries_the_initial_map_back_exactly() {
        let (mesh, population, loops, x) = disk();
        let coarse = Coarse::build(&mesh, &population, &loops, &[7], &x)
            .unwrap()
            .expect("a coarse copy");
        assert!(coarse.mesh.n_vertices() < mesh.n_vertices() / 2);
        // The same loops, the same populations in all.
        assert_eq!(coarse.loops.len(), loops.len());
        for (c, f) in coarse.loops.iter().zip(&loops) {
            assert_eq!(c.len(), f.len());
        }
        let (pc, pf): (f64, f64) = (coarse.population.iter().sum(), population.iter().sum());
        assert!((pc - pf).abs() < 1e-12 * pf, "{pc} vs {pf}");
        assert!(coarse.population.iter().all(|&p| p > 0.0));
        // Following the coarse initial map gives back the fine initial map.
        let y = coarse.follow(&coarse.initial);
        for (a, b) in x.iter().zip(&y) {
            assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
        }
        // The vertex asked to be kept is a coarse vertex: it follows exactly.
        let layout = Layout::new(&mesh, &loops);
        let moved: Vec<[f64; 3]> = coarse
            .initial
            .iter()
            .map(|p| [1.1 * p[0], 1.1 * p[1], 0.0])
            .collect();
        let z = coarse
            .prolong(&moved, &mesh, &population, &layout)
            .unwrap()
            .unwrap();
        assert!((z[7][0] - 1.1 * x[7][0]).abs() < 1e-12);
    }

    #[test]
    fn a_carried_map_that_folds_is_untangled_with_the_loops_where_the_coarse_map_put_them() {
        let (mesh, population, loops, x) = disk();
        let coarse = Coarse::build(&mesh, &population, &loops, &[], &x)
            .unwrap()
            .unwrap();
        let layout = Layout::new(&mesh, &loops);
        // Swirl the coarse map's interior sharply near one point, so that fine triangles
        // straddling coarse edges fold; the loops stay.
        let mut on_loop = vec![false; coarse.mesh.n_vertices()];
        for &v in coarse.loops.iter().flatten() {
            on_loop[v as usize] = true;
        }
        let g: Vec<[f64; 3]> = coarse
            .initial
            .iter()
            .enumerate()
            .map(|(v, p)| {
                if on_loop[v] {
                    return *p;
                }
                let (dx, dy) = (p[0] - 0.0, p[1] - 0.55);
                let turn = 1.5 * (-(dx * dx + dy * dy) / 0.005).exp();
                let (s, c) = turn.sin_cos();
                [dx * c - dy * s, 0.55 + dx * s + dy * c, 0.0]
            })
            .collect();
        assert_eq!(
            count_nonpositive(&g, &coarse.mesh.faces),
            0,
            "the coarse map must not fold"
        );
        let folds = count_nonpositive(&coarse.follow(&g), &mesh.faces);
        let y = coarse
            .prolong(&g, &mesh, &population, &layout)
            .unwrap()
            .unwrap();
        assert_eq!(
            count_nonpositive(&y, &mesh.faces),
            0,
            "{folds} folds were not untangled"
        );
        for &v in loops.iter().flatten() {
            assert_eq!(y[v as usize], coarse.follow(&g)[v as usize]);
        }
    }
}
