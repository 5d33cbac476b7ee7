//! The cartogram's mesh: the regions and the sea around them triangulated as one disk (DEM
//! paper §6.1 with GN's sea, §3): a rectangle some margin beyond the regions' bounding box is
//! filled with a hexagonal lattice of points, every region edge is split into pieces no longer
//! than the lattice spacing and kept as a chain of constrained edges, and the constrained
//! Delaunay triangulation of it all is taken. Every face then lies in exactly one region or in
//! the sea (gaps, lakes inside holes, the outside).

use super::regions::{Buckets, RegionSet, bbox, max2, min2};
use crate::mesh::triangulate::constrained_delaunay;
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
        for ([a, b], _) in &edges {
            let chain = subdivide(&mut points, *a, *b, h, &mut segments);
            chains.insert([*a, *b], chain);
        }
        let corners = [flo, [fhi[0], flo[1]], fhi, [flo[0], fhi[1]]];
        let c0 = points.len();
        points.extend_from_slice(&corners);
        for k in 0..4 {
            subdivide(&mut points, c0 + k, c0 + (k + 1) % 4, h, &mut segments);
        }

        // The lattice, clear of the region edges and the frame.
        let mut grid = Buckets::new(flo, fhi, edges.len());
        for (i, ([a, b], _)) in edges.iter().enumerate() {
            let (pa, pb) = (set.points[*a], set.points[*b]);
            grid.add_box(min2(pa, pb, 0.0), max2(pa, pb, 0.0), i);
        }
        let clear = CLEARANCE * h;
        let dy = 0.5 * 3f64.sqrt() * h;
        let rows = ((fhi[1] - flo[1]) / dy).floor() as usize;
        for j in 1..=rows {
            let y = flo[1] + j as f64 * dy;
            let shift = if j % 2 == 0 { 0.0 } else { 0.5 * h };
            let mut x = flo[0] + shift;
            while x < fhi[0] {
                let p = [x, y];
                x += h;
                if p[0] - flo[0] < clear
                    || fhi[0] - p[0] < clear
                    || p[1] - flo[1] < clear
                    || fhi[1] - p[1] < clear
                {
                    continue;
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
                if !near {
                    points.push(p);
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

/// Splits the segment `a`–`b` into `⌈|ab| / h⌉` equal pieces: adds the inner points to
/// `points`, the pieces to `segments`, and returns the inner points' indices from `a` to `b`.
fn subdivide(
    points: &mut Vec<[f64; 2]>,
    a: usize,
    b: usize,
    h: f64,
    segments: &mut Vec<[usize; 2]>,
) -> Vec<usize> {
    let (pa, pb) = (points[a], points[b]);
    let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
    let n = ((len / h).ceil() as usize).max(1);
    let mut chain = Vec::with_capacity(n - 1);
    let mut prev = a;
    for k in 1..n {
        let t = k as f64 / n as f64;
        points.push([pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])]);
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
                if clash.is_some() || !inside(ring_points, rings, centroids[f]) {
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

/// Even–odd test of `c` against the rings (vertex indices into `points`).
fn inside(points: &[[f64; 2]], rings: &[Vec<usize>], c: [f64; 2]) -> bool {
    let mut odd = false;
    for ring in rings {
        for i in 0..ring.len() {
            let a = points[ring[i]];
            let b = points[ring[(i + 1) % ring.len()]];
            if (a[1] > c[1]) != (b[1] > c[1]) {
                let x = a[0] + (c[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if x > c[0] {
                    odd = !odd;
                }
            }
        }
    }
    odd
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
    fn a_region_inside_another_is_an_overlap() {
        let a = raw(vec![vec![square(0.0, 0.0, 3.0)]], "feature 0");
        let b = raw(vec![vec![square(1.0, 1.0, 1.0)]], "feature 1");
        let set = RegionSet::build(&[a, b], "t").unwrap();
        let e = RegionMesh::build(&set, 500, "t").unwrap_err().to_string();
        assert!(e.contains("feature 0 overlaps feature 1"), "{e}");
    }
}
