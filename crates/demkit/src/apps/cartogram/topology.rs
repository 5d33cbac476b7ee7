//! The checks and repairs of a region set's topology as it is built: T-junctions split (a
//! vertex lying on another region's edge), holes inside their exterior, and crossing edges
//! refused (a ring crossing itself, regions overlapping), except the slight overlaps of
//! borders that were not shared exactly, which are kept with a warning.

use super::buckets::{Grid, SegmentGrid};
use super::regions::RegionSet;
use super::rings::{bbox, inside_ring, max2, min2, orient, segment_distance};
use crate::{Error, Result};
use std::collections::HashMap;

/// Regions whose borders cross are read when no vertex of one lies deeper inside the other
/// than this fraction of the map's diagonal (the slivers of unshared borders), and refused as
/// overlapping otherwise.
const OVERLAP_DEPTH: f64 = 2e-3;

impl RegionSet {
    /// Every hole lies inside its polygon's exterior ring. With no two edges crossing (checked
    /// first), a hole is wholly inside or wholly outside, so the middle of one of its edges
    /// decides.
    pub(super) fn check_holes_inside(&self, path: &str) -> Result<()> {
        let pts = &self.points;
        for r in &self.regions {
            for (k, rings) in r.polygons.iter().enumerate() {
                let exterior: Vec<[f64; 2]> = rings[0].iter().map(|&v| pts[v]).collect();
                for (j, hole) in rings.iter().enumerate().skip(1) {
                    let (a, b) = (pts[hole[0]], pts[hole[1]]);
                    let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
                    if !inside_ring(mid, &exterior) {
                        return Err(Error::Format {
                            path: path.to_string(),
                            msg: format!(
                                "{}: ring {j} of polygon {k} (a hole) lies outside the polygon's \
                                 exterior ring",
                                r.label
                            ),
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Inserts into every edge the vertices lying on it (within `tol`), in order.
    pub(super) fn split_t_junctions(&mut self, tol: f64) {
        let edges = self.edges();
        let grid = Grid::new(&self.points, self.points.len());
        let mut inner: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        for ([a, b], _) in &edges {
            let (pa, pb) = (self.points[*a], self.points[*b]);
            let d = [pb[0] - pa[0], pb[1] - pa[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let mut on: Vec<(f64, usize)> = Vec::new();
            grid.visit_box(min2(pa, pb, -tol), max2(pa, pb, tol), |v| {
                if v == *a || v == *b {
                    return;
                }
                let p = self.points[v];
                let w = [p[0] - pa[0], p[1] - pa[1]];
                let t = (w[0] * d[0] + w[1] * d[1]) / len2;
                let cross = w[0] * d[1] - w[1] * d[0];
                if t > 0.0 && t < 1.0 && cross.abs() <= tol * len2.sqrt() {
                    on.push((t, v));
                }
            });
            if !on.is_empty() {
                on.sort_by(|x, y| x.0.total_cmp(&y.0));
                inner.insert([*a, *b], on.into_iter().map(|(_, v)| v).collect());
            }
        }
        if inner.is_empty() {
            return;
        }
        for ring in self
            .regions
            .iter_mut()
            .flat_map(|r| r.polygons.iter_mut().flatten())
        {
            let mut out = Vec::with_capacity(ring.len());
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                out.push(a);
                if let Some(mid) = inner.get(&[a.min(b), a.max(b)]) {
                    if a < b {
                        out.extend(mid.iter().copied());
                    } else {
                        out.extend(mid.iter().rev().copied());
                    }
                }
            }
            *ring = out;
        }
    }

    /// Refuses edges that cross each other properly (they share no endpoint).
    pub(super) fn check_crossings(&mut self, path: &str) -> Result<()> {
        let edges = self.edges();
        let pts = &self.points;
        let mids: Vec<[f64; 2]> = edges
            .iter()
            .map(|([a, b], _)| {
                [
                    0.5 * (pts[*a][0] + pts[*b][0]),
                    0.5 * (pts[*a][1] + pts[*b][1]),
                ]
            })
            .collect();
        let grid = SegmentGrid::new(pts, &edges);
        // Pairs of regions whose edges cross, with where they first do.
        let mut pairs: Vec<((usize, usize), [f64; 2])> = Vec::new();
        for (i, ([a, b], owners)) in edges.iter().enumerate() {
            let (pa, pb) = (pts[*a], pts[*b]);
            let mut found = Vec::new();
            grid.visit_box(min2(pa, pb, 0.0), max2(pa, pb, 0.0), |j| {
                if j <= i {
                    return;
                }
                let ([c, d], _) = &edges[j];
                if a == c || a == d || b == c || b == d {
                    return;
                }
                let (pc, pd) = (pts[*c], pts[*d]);
                let o1 = orient(pa, pb, pc);
                let o2 = orient(pa, pb, pd);
                let o3 = orient(pc, pd, pa);
                let o4 = orient(pc, pd, pb);
                if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
                    found.push(j);
                }
            });
            for j in found {
                let other = &edges[j].1;
                let at = mids[i];
                let r1 = owners[0];
                match other.iter().find(|&&r| r != r1) {
                    Some(&r2) if !owners.contains(&r2) => {
                        let key = (r1.min(r2), r1.max(r2));
                        if !pairs.iter().any(|(k, _)| *k == key) {
                            pairs.push((key, at));
                        }
                    }
                    _ => {
                        return Err(Error::Format {
                            path: path.to_string(),
                            msg: format!(
                                "{}: its boundary crosses itself near ({}, {})",
                                self.regions[r1].label, at[0], at[1]
                            ),
                        });
                    }
                }
            }
        }
        let (lo, hi) = bbox(pts.iter().copied());
        let limit = OVERLAP_DEPTH * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        for ((r1, r2), at) in pairs {
            let depth = self.overlap_depth(r1, r2).max(self.overlap_depth(r2, r1));
            let (l1, l2) = (&self.regions[r1].label, &self.regions[r2].label);
            if depth > limit {
                return Err(Error::Format {
                    path: path.to_string(),
                    msg: format!(
                        "{l1} overlaps {l2}: their edges cross near ({}, {})",
                        at[0], at[1]
                    ),
                });
            }
            self.warnings.push(format!(
                "{l1} and {l2}: their borders overlap slightly (by up to {:.2e} of the map's \
                 diagonal); left as they are",
                depth / (limit / OVERLAP_DEPTH)
            ));
        }
        Ok(())
    }

    /// How far the vertices of region `a` reach inside region `b`: the largest distance from
    /// a vertex of `a` inside `b` to `b`'s boundary (0 when none is inside).
    fn overlap_depth(&self, a: usize, b: usize) -> f64 {
        let pts = &self.points;
        let rings_b: Vec<Vec<[f64; 2]>> = self.regions[b]
            .polygons
            .iter()
            .flatten()
            .map(|r| r.iter().map(|&v| pts[v]).collect())
            .collect();
        let mut depth = 0.0f64;
        for &v in self.regions[a].polygons.iter().flatten().flatten() {
            let p = pts[v];
            let inside = rings_b.iter().filter(|r| inside_ring(p, r)).count() % 2 == 1;
            if !inside {
                continue;
            }
            let mut d = f64::INFINITY;
            for r in &rings_b {
                for i in 0..r.len() {
                    d = d.min(segment_distance(p, r[i], r[(i + 1) % r.len()]));
                }
            }
            depth = depth.max(d);
        }
        depth
    }
}
