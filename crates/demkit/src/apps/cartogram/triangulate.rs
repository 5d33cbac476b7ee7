//! The cartogram's mesh: the regions and the sea around them triangulated as one disk (DEM
//! paper §6.1 with GN's sea, §3): a rectangle some margin beyond the regions' bounding box is
//! filled with a hexagonal lattice of points, every region edge is split into pieces no longer
//! than the lattice spacing and kept as a chain of constrained edges, and the constrained
//! Delaunay triangulation of it all is taken. Every face then lies in exactly one region or in
//! the sea (gaps, lakes inside holes, the outside).

use super::regions::{Buckets, RegionSet, bbox, max2, min2};
use crate::mesh::triangulate::{constrained_delaunay, inside_loops};
use crate::{Error, Result};
use std::collections::HashMap;

/// The sea's margin around the regions, as a fraction of their bounding box's larger side.
const MARGIN: f64 = 0.2;

/// Lattice points closer than this fraction of the spacing to a region edge or the frame are
/// left out (the edge's own points are there).
const CLEARANCE: f64 = 0.5;

/// A triangulated disk containing the regions.
#[derive(Debug, Clone)]
pub struct RegionMesh {
    /// Mesh vertices: first the regions' vertices ([`RegionSet::points`], same indices), then the
    /// points added on region edges, on the frame and in the lattice.
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise faces.
    pub faces: Vec<[u32; 3]>,
    /// The region each face lies in (`None`: the sea).
    pub face_region: Vec<Option<usize>>,
    /// For every region edge `[a, b]` with `a < b`, the mesh vertices added on it, from `a` to `b`.
    chains: HashMap<[usize; 2], Vec<usize>>,
}

impl RegionMesh {
    /// Triangulates `set` and its sea with about `target_faces` faces; `path` names the file in
    /// messages.
    ///
    /// Errors: [`Error::Format`] when two regions (or two polygons of one region) overlap without
    /// their edges crossing (one inside the other, or the same polygon twice), or a region ends
    /// up with no face; the triangulation's own errors.
    pub fn build(set: &RegionSet, target_faces: usize, path: &str) -> Result<RegionMesh> {
        let (lo, hi) = bbox(set.points.iter().copied());
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let m = MARGIN * size;
        let (flo, fhi) = ([lo[0] - m, lo[1] - m], [hi[0] + m, hi[1] + m]);
        let frame_area = (fhi[0] - flo[0]) * (fhi[1] - flo[1]);
        // A hexagonal lattice of spacing h has 2/(√3 h²) points per unit area, and a
        // triangulation about twice as many faces as points.
        let h = (4.0 * frame_area / (3f64.sqrt() * target_faces.max(16) as f64)).sqrt();

        let mut points = set.points.clone();
        let mut segments: Vec<[usize; 2]> = Vec::new();
        let mut chains = HashMap::new();
        let edges = set.edges();
        let sizing = Sizing::new(set, h);
        for ([a, b], _) in &edges {
            let chain = subdivide(&mut points, *a, *b, &|p| sizing.at(p), &mut segments);
            chains.insert([*a, *b], chain);
        }
        let corners = [flo, [fhi[0], flo[1]], fhi, [flo[0], fhi[1]]];
        let c0 = points.len();
        points.extend_from_slice(&corners);
        for k in 0..4 {
            subdivide(&mut points, c0 + k, c0 + (k + 1) % 4, &|_| h, &mut segments);
        }

        // The lattice, clear of the region edges and the frame.
        let mut grid = Buckets::new(flo, fhi, edges.len());
        for (i, ([a, b], _)) in edges.iter().enumerate() {
            let (pa, pb) = (set.points[*a], set.points[*b]);
            grid.add_box(min2(pa, pb, 0.0), max2(pa, pb, 0.0), i);
        }
        let clear_of_edges = |p: [f64; 2], clear: f64| {
            if p[0] - flo[0] < clear
                || fhi[0] - p[0] < clear
                || p[1] - flo[1] < clear
                || fhi[1] - p[1] < clear
            {
                return false;
            }
            let mut near = false;
            grid.visit(
                [p[0] - clear, p[1] - clear],
                [p[0] + clear, p[1] + clear],
                |i| {
                    if !near {
                        let [a, b] = edges[i].0;
                        near = segment_distance(p, set.points[a], set.points[b]) < clear;
                    }
                },
            );
            !near
        };
        let dy = 0.5 * 3f64.sqrt() * h;
        let rows = ((fhi[1] - flo[1]) / dy).floor() as usize;
        for j in 1..=rows {
            let y = flo[1] + j as f64 * dy;
            let shift = if j % 2 == 0 { 0.0 } else { 0.5 * h };
            let mut x = flo[0] + shift;
            while x < fhi[0] {
                let p = [x, y];
                x += h;
                if sizing.at(p) >= h && clear_of_edges(p, CLEARANCE * h) {
                    points.push(p);
                }
            }
        }
        // Finer points around small polygons: quadtree cells split until no larger than the
        // spacing wanted at their centre, a point at the centre of each leaf.
        let mut done = std::collections::HashSet::new();
        for z in &sizing.small {
            let reach = (h - z.2) / GRADING;
            let cell = |x: f64, k: usize| ((x - flo[k]) / h).floor().max(0.0) as i64;
            for i in cell(z.0[0] - reach, 0)..=cell(z.1[0] + reach, 0) {
                for j in cell(z.0[1] - reach, 1)..=cell(z.1[1] + reach, 1) {
                    if done.insert((i, j)) {
                        let lo = [flo[0] + i as f64 * h, flo[1] + j as f64 * h];
                        quadtree(lo, h, &sizing, &mut |c, s| {
                            if s < h && clear_of_edges(c, CLEARANCE * s) {
                                points.push(c);
                            }
                        });
                    }
                }
            }
        }

        let t = constrained_delaunay(&points, &segments)?;
        let polygons: Vec<(usize, Vec<Vec<usize>>)> = set
            .regions
            .iter()
            .enumerate()
            .flat_map(|(r, region)| region.polygons.iter().map(move |p| (r, p.clone())))
            .collect();
        let face_region = assign_faces(set, &polygons, &set.points, &t.points, &t.faces, path)?;
        let mut has_face = vec![false; set.regions.len()];
        for r in face_region.iter().flatten() {
            has_face[*r] = true;
        }
        if let Some(r) = has_face.iter().position(|&x| !x) {
            return Err(Error::Format {
                path: path.to_string(),
                msg: format!("{}: the region encloses no area", set.regions[r].label),
            });
        }
        Ok(RegionMesh {
            points: t.points,
            faces: t.faces,
            face_region,
            chains,
        })
    }

    /// The mesh vertices along a ring of region vertices: every ring vertex followed by the
    /// vertices added on its edge to the next one.
    pub fn dense_ring(&self, ring: &[usize]) -> Vec<usize> {
        let mut out = Vec::with_capacity(ring.len());
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            out.push(a);
            if let Some(mid) = self.chains.get(&[a.min(b), a.max(b)]) {
                if a < b {
                    out.extend(mid.iter().copied());
                } else {
                    out.extend(mid.iter().rev().copied());
                }
            }
        }
        out
    }
}

/// A polygon gets finer spacing when spacing h would give it fewer faces than this.
const MIN_POLYGON_FACES: f64 = 100.0;

/// How fast the finer spacing around a small polygon grows back to h, per unit distance.
const GRADING: f64 = 0.5;

/// The spacing wanted across the mesh: h, except around polygons too small to get
/// [`MIN_POLYGON_FACES`] faces at spacing h, where it is `s_p = √(2 A_p / MIN_POLYGON_FACES)`
/// (at least h/64) on the polygon's bounding box and grows by [`GRADING`] with the distance.
struct Sizing {
    h: f64,
    /// Bounding box and spacing of each small polygon.
    small: Vec<([f64; 2], [f64; 2], f64)>,
}

impl Sizing {
    fn new(set: &RegionSet, h: f64) -> Self {
        let mut small = Vec::new();
        for region in &set.regions {
            for rings in &region.polygons {
                let coords: Vec<Vec<[f64; 2]>> = rings
                    .iter()
                    .map(|r| r.iter().map(|&v| set.points[v]).collect())
                    .collect();
                let area = super::regions::polygon_area(&coords).abs();
                let s = (2.0 * area / MIN_POLYGON_FACES).sqrt().max(h / 64.0);
                if s < h {
                    let (lo, hi) = bbox(coords[0].iter().copied());
                    small.push((lo, hi, s));
                }
            }
        }
        Sizing { h, small }
    }

    /// The spacing wanted at `p`.
    fn at(&self, p: [f64; 2]) -> f64 {
        self.small.iter().fold(self.h, |m, (lo, hi, s)| {
            let dx = (lo[0] - p[0]).max(p[0] - hi[0]).max(0.0);
            let dy = (lo[1] - p[1]).max(p[1] - hi[1]).max(0.0);
            m.min(s + GRADING * (dx * dx + dy * dy).sqrt())
        })
    }
}

/// Visits the leaves of the quadtree over the square at `lo` of side `size` whose cells are
/// split until no larger than the spacing at their centre: `leaf(centre, spacing)`.
fn quadtree(lo: [f64; 2], size: f64, sizing: &Sizing, leaf: &mut dyn FnMut([f64; 2], f64)) {
    let c = [lo[0] + 0.5 * size, lo[1] + 0.5 * size];
    let s = sizing.at(c);
    if size <= s * 1.000_001 {
        leaf(c, s);
        return;
    }
    let half = 0.5 * size;
    for (dx, dy) in [(0.0, 0.0), (half, 0.0), (0.0, half), (half, half)] {
        quadtree([lo[0] + dx, lo[1] + dy], half, sizing, leaf);
    }
}

/// Splits the segment `a`–`b` into pieces about as long as the spacing wanted along it
/// (`spacing`, evaluated at both ends of each piece), stretched evenly to end at `b`: adds the
/// inner points to `points`, the pieces to `segments`, and returns the inner points' indices
/// from `a` to `b`.
fn subdivide(
    points: &mut Vec<[f64; 2]>,
    a: usize,
    b: usize,
    spacing: &dyn Fn([f64; 2]) -> f64,
    segments: &mut Vec<[usize; 2]>,
) -> Vec<usize> {
    let (pa, pb) = (points[a], points[b]);
    let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
    let at = |t: f64| [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])];
    // Parameters of the piece ends, greedily; then scaled so that the last one is exactly 1.
    let mut ts = vec![0.0];
    let mut t = 0.0;
    while t < 1.0 {
        let mut step = spacing(at(t)) / len;
        for _ in 0..2 {
            step = step.min(spacing(at((t + step).min(1.0))) / len);
        }
        t += step.max(1e-9);
        ts.push(t);
    }
    // When the last piece overshoots by more than half its length, stretch instead of shrink.
    let n = ts.len();
    if n > 2 && ts[n - 1] - 1.0 > 0.5 * (ts[n - 1] - ts[n - 2]) {
        ts.pop();
    }
    let last = *ts.last().unwrap_or(&1.0);
    let mut chain = Vec::with_capacity(ts.len());
    let mut prev = a;
    for &t in &ts[1..ts.len() - 1] {
        points.push(at(t / last));
        let v = points.len() - 1;
        segments.push([prev, v]);
        chain.push(v);
        prev = v;
    }
    segments.push([prev, b]);
    chain
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let w = [p[0] - a[0], p[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        ((w[0] * d[0] + w[1] * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((w[0] - t * d[0]).powi(2) + (w[1] - t * d[1]).powi(2)).sqrt()
}

/// The region of every face: the one polygon (even–odd over its rings) containing the face's
/// centroid, or `None`. A face inside two polygons is an overlap, refused. `polygons` are
/// (region, rings) with rings given as indices into `ring_points`.
pub(super) fn assign_faces(
    set: &RegionSet,
    polygons: &[(usize, Vec<Vec<usize>>)],
    ring_points: &[[f64; 2]],
    points: &[[f64; 2]],
    faces: &[[u32; 3]],
    path: &str,
) -> Result<Vec<Option<usize>>> {
    let centroids: Vec<[f64; 2]> = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| points[v as usize]);
            [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]
        })
        .collect();
    let (lo, hi) = bbox(centroids.iter().copied());
    let mut grid = Buckets::new(lo, hi, centroids.len());
    for (f, &c) in centroids.iter().enumerate() {
        grid.add_box(c, c, f);
    }
    // (region, polygon) of each face.
    let mut owner: Vec<Option<(usize, usize)>> = vec![None; faces.len()];
    for (k, (r, rings)) in polygons.iter().enumerate() {
        let (r, region) = (*r, &set.regions[*r]);
        {
            let (plo, phi) = bbox(rings.iter().flatten().map(|&v| ring_points[v]));
            let mut clash = None;
            grid.visit(plo, phi, |f| {
                if clash.is_some() || !inside_loops(ring_points, rings, centroids[f]) {
                    return;
                }
                match owner[f] {
                    None => owner[f] = Some((r, k)),
                    Some(o) => clash = Some((o, f)),
                }
            });
            if let Some(((r0, _), f)) = clash {
                let c = centroids[f];
                let msg = if r0 == r {
                    format!(
                        "{}: its polygons overlap near ({}, {})",
                        region.label, c[0], c[1]
                    )
                } else {
                    format!(
                        "{} overlaps {} near ({}, {})",
                        set.regions[r0].label, region.label, c[0], c[1]
                    )
                };
                return Err(Error::Format {
                    path: path.to_string(),
                    msg,
                });
            }
        }
    }
    Ok(owner.into_iter().map(|o| o.map(|(r, _)| r)).collect())
}

#[cfg(test)]
mod tests {
    use super::super::geojson::RawRegion;
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
    }

    fn raw(polygons: Vec<Vec<Vec<[f64; 2]>>>, label: &str) -> RawRegion {
        RawRegion {
            label: label.into(),
            value: 1.0,
            multi: false,
            polygons,
        }
    }

    fn area(p: &[[f64; 2]], f: [u32; 3]) -> f64 {
        let [a, b, c] = f.map(|v| p[v as usize]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    }

    #[test]
    fn faces_tile_regions_and_sea_exactly() {
        // A 3×3 square with a 1×1 hole, and a unit square beside it.
        let a = raw(
            vec![vec![square(0.0, 0.0, 3.0), square(1.0, 1.0, 1.0)]],
            "A",
        );
        let b = raw(vec![vec![square(3.0, 0.0, 1.0)]], "B");
        let set = RegionSet::build(&[a, b], "t").unwrap();
        let m = RegionMesh::build(&set, 2000, "t").unwrap();
        assert!(
            m.faces.len() > 1000 && m.faces.len() < 4000,
            "{}",
            m.faces.len()
        );
        let mut per = [0.0; 3];
        for (f, r) in m.faces.iter().zip(&m.face_region) {
            let a = area(&m.points, *f);
            assert!(a > 0.0);
            per[r.map_or(2, |r| r)] += a;
        }
        assert!(
            (per[0] - 8.0).abs() < 1e-9 && (per[1] - 1.0).abs() < 1e-9,
            "{per:?}"
        );
        // Frame: 4 × 3 box with a margin of 0.8 on each side.
        assert!((per[0] + per[1] + per[2] - 5.6 * 4.6).abs() < 1e-9);
        // The shared edge (3,0)–(3,1) is a chain of mesh edges with the same points both ways.
        let ring_a = &set.regions[0].polygons[0][0];
        let dense = m.dense_ring(ring_a);
        assert!(dense.len() > 30);
        for w in dense.windows(2) {
            let has = m.faces.iter().any(|f| {
                (0..3).any(|k| {
                    let (p, q) = (f[k] as usize, f[(k + 1) % 3] as usize);
                    (p, q) == (w[0], w[1]) || (p, q) == (w[1], w[0])
                })
            });
            assert!(has, "ring piece {w:?} is not a mesh edge");
        }
    }

    #[test]
    fn subdivision_follows_the_spacing() {
        let mut points = vec![[0.0, 0.0], [1.0, 0.0]];
        let mut segs = Vec::new();
        // Constant spacing 0.3 on a unit segment: three pieces of 1/3.
        let chain = subdivide(&mut points, 0, 1, &|_| 0.3, &mut segs);
        assert_eq!(chain.len(), 2);
        assert!(
            (points[2][0] - 1.0 / 3.0).abs() < 1e-12 && (points[3][0] - 2.0 / 3.0).abs() < 1e-12
        );
        assert_eq!(segs, vec![[0, 2], [2, 3], [3, 1]]);
        // Spacing growing away from x = 0: pieces grow along the segment.
        let chain = subdivide(&mut points, 0, 1, &|p| 0.01 + 0.5 * p[0], &mut segs);
        let xs: Vec<f64> = chain.iter().map(|&v| points[v][0]).collect();
        assert!(xs.len() > 5 && xs.len() < 20, "{xs:?}");
        assert!(xs.windows(3).all(|w| w[2] - w[1] > w[1] - w[0]), "{xs:?}");
    }

    #[test]
    fn a_small_region_gets_a_finer_mesh() {
        // A 0.05-wide square in the corner of a 4×4 block: at the block's spacing it would be
        // two triangles; the graded spacing gives it about MIN_POLYGON_FACES.
        let big = vec![
            [0.05, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
            [0.0, 0.05],
            [0.05, 0.05],
        ];
        let a = raw(vec![vec![big]], "big");
        let b = raw(vec![vec![square(0.0, 0.0, 0.05)]], "small");
        let set = RegionSet::build(&[a, b], "t").unwrap();
        let m = RegionMesh::build(&set, 2000, "t").unwrap();
        let n_small = m.face_region.iter().filter(|r| **r == Some(1)).count();
        assert!((50..400).contains(&n_small), "{n_small}");
        let small_area: f64 = m
            .faces
            .iter()
            .zip(&m.face_region)
            .filter(|(_, r)| **r == Some(1))
            .map(|(f, _)| area(&m.points, *f))
            .sum();
        assert!((small_area - 0.0025).abs() < 1e-12);
        let plain =
            RegionSet::build(&[raw(vec![vec![square(0.0, 0.0, 4.0)]], "big")], "t").unwrap();
        let n_plain = RegionMesh::build(&plain, 2000, "t").unwrap().faces.len();
        assert!(
            m.faces.len() < n_plain + 1000,
            "{} vs {n_plain}",
            m.faces.len()
        );
    }

    #[test]
    fn a_region_inside_another_is_an_overlap() {
        let a = raw(vec![vec![square(0.0, 0.0, 3.0)]], "feature 0");
        let b = raw(vec![vec![square(1.0, 1.0, 1.0)]], "feature 1");
        let set = RegionSet::build(&[a, b], "t").unwrap();
        let e = RegionMesh::build(&set, 500, "t").unwrap_err().to_string();
        assert!(e.contains("feature 0 overlaps feature 1"), "{e}");
    }
}
