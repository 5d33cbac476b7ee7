//! Shape improvement of a remeshed surface, done in the map's domain so that every vertex stays
//! on the input surface: edge flips towards the Delaunay condition measured on the surface, and
//! a density-weighted centroidal smoothing of the free vertices, each move computed on the
//! surface and carried into the domain through the inverse of the map's Jacobian. A map is
//! never exactly conformal (its Beltrami coefficient stretches a uniform domain lattice into
//! skewed triangles, DEQ paper §3) nor exactly density-equalizing; both steps undo part of that.
//! Flips and moves are only made when every triangle stays positively oriented in the domain,
//! so the result remains a triangulation of the same surface with the same topology.

use super::chart::{Chart, ChartPoint};
use crate::geometry::{cross, dot, norm, sub, triangle_area};
use std::collections::{HashMap, HashSet};

/// A triangulation of the domain with its points on the surface.
pub struct Draft {
    /// Per vertex, its place in the domain, its input face (`usize::MAX` when fixed) and its
    /// position on the surface.
    pub points: Vec<ChartPoint>,
    /// Vertices that must not move (boundary points).
    pub fixed: Vec<bool>,
    /// Faces oriented like the input's.
    pub faces: Vec<[u32; 3]>,
}

/// Smoothing weights grow as this power of the population per unit area: a centroidal
/// smoothing with triangle weights w makes edge lengths scale like w^(−1/3), so vertex density
/// (∝ length⁻²) follows the population density when w = density^1.5.
const DENSITY_EXPONENT: f64 = 1.5;

/// At most this many flip passes in a row.
const FLIP_PASSES: usize = 8;

/// Runs `rounds` rounds of (flips, one smoothing sweep), then flips once more. `density` is
/// the population per unit area of every input face.
pub fn relax(draft: &mut Draft, chart: &Chart, density: &[f64], rounds: usize) {
    let weight = |p: &ChartPoint| -> f64 {
        if p.face == usize::MAX {
            f64::NAN
        } else {
            density[p.face].powf(DENSITY_EXPONENT)
        }
    };
    for _ in 0..rounds {
        flips(draft, chart);
        let mut w: Vec<f64> = draft.points.iter().map(weight).collect();
        fill_fixed_weights(draft, &mut w);
        smooth(draft, chart, density, &mut w);
    }
    flips(draft, chart);
}

/// Fixed vertices take the mean weight of their free neighbours (1 if none).
fn fill_fixed_weights(draft: &Draft, w: &mut [f64]) {
    let mut sum = vec![(0.0, 0usize); w.len()];
    for f in &draft.faces {
        for k in 0..3 {
            let (v, u) = (f[k] as usize, f[(k + 1) % 3] as usize);
            if w[v].is_nan() && !w[u].is_nan() {
                sum[v].0 += w[u];
                sum[v].1 += 1;
            }
        }
    }
    for (v, x) in w.iter_mut().enumerate() {
        if x.is_nan() {
            *x = if sum[v].1 > 0 {
                sum[v].0 / sum[v].1 as f64
            } else {
                1.0
            };
        }
    }
}

/// One Gauss–Seidel sweep: each free vertex moves towards the weighted centroid of its
/// triangles (weight × area), on the surface.
fn smooth(draft: &mut Draft, chart: &Chart, density: &[f64], w: &mut [f64]) {
    let n = draft.points.len();
    let (offsets, ids) = crate::mesh::vertex_faces(n, &draft.faces);
    for v in 0..n {
        if draft.fixed[v] {
            continue;
        }
        let ring = &ids[offsets[v]..offsets[v + 1]];
        let (mut acc, mut total) = ([0.0; 3], 0.0);
        for &f in ring {
            let face = draft.faces[f as usize];
            let p = face.map(|u| draft.points[u as usize].position);
            let wt = face.iter().map(|&u| w[u as usize]).sum::<f64>() / 3.0;
            let m = wt * triangle_area(p[0], p[1], p[2]);
            for d in 0..3 {
                acc[d] += m * (p[0][d] + p[1][d] + p[2][d]) / 3.0;
            }
            total += m;
        }
        if !(total > 0.0) {
            continue;
        }
        let here = draft.points[v];
        let step = sub(acc.map(|x| x / total), here.position);
        for lambda in [1.0, 0.5, 0.25] {
            let Some(q) = chart.displaced(here.domain, here.face, step.map(|x| x * lambda)) else {
                break;
            };
            let Some(moved) = chart.pull(q) else {
                continue;
            };
            let valid = ring.iter().all(|&f| {
                let c = draft.faces[f as usize].map(|u| {
                    if u as usize == v {
                        q
                    } else {
                        draft.points[u as usize].domain
                    }
                });
                chart.orientation(c[0], c[1], c[2]) > 0.0
            });
            if valid {
                draft.points[v] = moved;
                w[v] = density[moved.face].powf(DENSITY_EXPONENT);
                break;
            }
        }
    }
}

/// Flip passes until none flips (or [`FLIP_PASSES`] ran).
fn flips(draft: &mut Draft, chart: &Chart) {
    for _ in 0..FLIP_PASSES {
        if flip_pass(draft, chart) == 0 {
            break;
        }
    }
}

/// Flips every interior edge whose two opposite angles on the surface sum to more than π, when
/// the two new triangles are positively oriented in the domain, do not fold on the surface,
/// the new edge is not already there and both end points keep at least three faces. Each face
/// takes part in one flip per pass. Returns the number of flips.
fn flip_pass(draft: &mut Draft, chart: &Chart) -> usize {
    let faces = &mut draft.faces;
    let mut half: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * faces.len());
    let mut degree = vec![0usize; draft.points.len()];
    for (i, f) in faces.iter().enumerate() {
        for k in 0..3 {
            half.insert((f[k], f[(k + 1) % 3]), i);
            degree[f[k] as usize] += 1;
        }
    }
    let mut touched = vec![false; faces.len()];
    let mut created: HashSet<(u32, u32)> = HashSet::new();
    let mut count = 0;
    let pos = |v: u32| draft.points[v as usize].position;
    let dom = |v: u32| draft.points[v as usize].domain;
    for i in 0..faces.len() {
        for k in 0..3 {
            if touched[i] {
                break;
            }
            let f = faces[i];
            let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
            if a > b {
                continue;
            }
            let Some(&j) = half.get(&(b, a)) else {
                continue;
            };
            if touched[j] {
                continue;
            }
            let g = faces[j];
            let d = g.iter().copied().find(|&x| x != a && x != b).unwrap_or(a);
            if d == a || degree[a as usize] <= 3 || degree[b as usize] <= 3 {
                continue;
            }
            let key = (c.min(d), c.max(d));
            if half.contains_key(&(c, d)) || half.contains_key(&(d, c)) || created.contains(&key) {
                continue;
            }
            let angle = |p: u32, x: u32, y: u32| {
                let (u, w) = (sub(pos(x), pos(p)), sub(pos(y), pos(p)));
                (dot(u, w) / (norm(u) * norm(w))).clamp(-1.0, 1.0).acos()
            };
            if angle(c, a, b) + angle(d, b, a) <= std::f64::consts::PI + 1e-9 {
                continue;
            }
            let (n1, n2) = ([a, d, c], [d, b, c]);
            let oriented = [n1, n2]
                .iter()
                .all(|t| chart.orientation(dom(t[0]), dom(t[1]), dom(t[2])) > 0.0);
            let normal = |t: [u32; 3]| cross(sub(pos(t[1]), pos(t[0])), sub(pos(t[2]), pos(t[0])));
            if !oriented || dot(normal(n1), normal(n2)) <= 0.0 {
                continue;
            }
            faces[i] = n1;
            faces[j] = n2;
            touched[i] = true;
            touched[j] = true;
            created.insert(key);
            degree[a as usize] -= 1;
            degree[b as usize] -= 1;
            degree[c as usize] += 1;
            degree[d as usize] += 1;
            count += 1;
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::super::{Target, quality::quality, remesh_with};
    use crate::TriMesh;
    use crate::mesh::topology::topology;

    /// A flat square of 2·k² triangles whose map stretches x by 4: a uniform lattice in the
    /// domain pulls back to triangles squeezed by 4 along x.
    fn squeezed(k: usize) -> (TriMesh, Vec<[f64; 3]>) {
        let input = crate::generate::square_grid(k, k, 1.0, 1.0).unwrap();
        let mapped = input
            .positions
            .iter()
            .map(|p| [4.0 * p[0], p[1], 0.0])
            .collect();
        (input, mapped)
    }

    #[test]
    fn relaxing_undoes_the_stretch_of_a_map() {
        let (input, mapped) = squeezed(10);
        let area = crate::geometry::face_areas(&input.positions, &input.faces);
        let plain = remesh_with(&input, &area, &mapped, Target::Plane, 400, 0).unwrap();
        let relaxed = remesh_with(&input, &area, &mapped, Target::Plane, 400, 10).unwrap();
        let (q0, q1) = (quality(&plain), quality(&relaxed));
        assert!(q0.median_min_angle_deg < 20.0, "{q0:?}");
        assert!(q1.median_min_angle_deg > 40.0, "{q1:?}");
        // Same vertex count and topology, every vertex still on the square.
        assert_eq!(plain.n_vertices(), relaxed.n_vertices());
        let t = topology(&relaxed);
        assert_eq!((t.boundary_loops.len(), t.genus), (1, 0));
        for p in &relaxed.positions {
            assert!(p[2] == 0.0 && (-1e-12..=1.0 + 1e-12).contains(&p[0]));
            assert!((-1e-12..=1.0 + 1e-12).contains(&p[1]));
        }
    }
}
