//! The checks and repairs of a region set's topology as it is built: T-junctions split (a
//! vertex lying on another region's edge), holes inside their exterior, and crossing edges
//! refused (a ring crossing itself, regions overlapping), except the slight overlaps of
//! borders that were not shared exactly, which are kept with a warning.

use super::buckets::Buckets;
use super::cleaning::remove_spikes;
use super::crossings::{crossing_point, proper_crossings};
use super::regions::RegionSet;
use super::rings::{bbox, closest_point, inside_ring, max2, min2, segment_distance};
use crate::{Error, Result};
use std::collections::HashMap;

/// Regions whose borders cross are read when no vertex of one lies deeper inside the other
/// than this fraction of the map's diagonal (the slivers of unshared borders), and refused as
/// overlapping otherwise.
const OVERLAP_DEPTH: f64 = 2e-3;

/// Two regions (lower index first) whose edges cross, and where they first do.
type Overlap = ((usize, usize), [f64; 2]);

/// Rounds of repair of slight overlaps before they are left as they are.
const OVERLAP_REPAIRS: usize = 3;

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

    /// Inserts into every edge the vertices lying on it, in order: those within `tol` of it,
    /// and those of other regions within `near` of it (a border not shared exactly: one
    /// region's vertex a little off its neighbour's edge).
    pub(super) fn split_t_junctions(&mut self, tol: f64, near: f64) {
        let edges = self.edges();
        let mut regions_of: Vec<Vec<usize>> = vec![Vec::new(); self.points.len()];
        for (r, region) in self.regions.iter().enumerate() {
            for &v in region.polygons.iter().flatten().flatten() {
                if !regions_of[v].contains(&r) {
                    regions_of[v].push(r);
                }
            }
        }
        let reach = tol.max(near);
        let grid = Buckets::of_points(&self.points);
        let mut inner: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        // Per region, the vertices of its neighbours taken onto its edges from off them.
        let mut joined = vec![0usize; self.regions.len()];
        for ([a, b], owners) in &edges {
            let (pa, pb) = (self.points[*a], self.points[*b]);
            let d = [pb[0] - pa[0], pb[1] - pa[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let mut on: Vec<(f64, usize)> = Vec::new();
            grid.visit(min2(pa, pb, -reach), max2(pa, pb, reach), |v| {
                if v == *a || v == *b {
                    return;
                }
                let p = self.points[v];
                let w = [p[0] - pa[0], p[1] - pa[1]];
                let t = (w[0] * d[0] + w[1] * d[1]) / len2;
                let off = (w[0] * d[1] - w[1] * d[0]).abs() / len2.sqrt();
                let other = !regions_of[v].iter().any(|r| owners.contains(r));
                if t > 0.0 && t < 1.0 && (off <= tol || (other && off <= near)) {
                    on.push((t, v));
                    if off > tol {
                        for &r in owners {
                            joined[r] += 1;
                        }
                    }
                }
            });
            if !on.is_empty() {
                on.sort_by(|x, y| x.0.total_cmp(&y.0));
                inner.insert([*a, *b], on.into_iter().map(|(_, v)| v).collect());
            }
        }
        for (r, count) in joined.into_iter().enumerate() {
            if count > 0 {
                self.warnings.push(format!(
                    "{}: its border and its neighbours' were not shared exactly; {count} of their \
                     vertices within {:.0e} of the map's diagonal of its edges were put on them",
                    self.regions[r].label,
                    near / (tol / super::regions::SNAP)
                ));
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

    /// Refuses edges that cross each other properly (they share no endpoint), except the
    /// slight overlaps of two regions' borders (no vertex deeper than [`OVERLAP_DEPTH`] inside
    /// the other region), which are repaired: the vertices of each region lying inside the
    /// other are moved onto the other's border ([`RegionSet::snap_overlap`]) and become shared
    /// vertices of it, with a warning naming the two regions. `tol` is the distance within
    /// which a vertex lies on an edge.
    pub(super) fn check_crossings(&mut self, path: &str, tol: f64) -> Result<()> {
        let (lo, hi) = bbox(self.points.iter().copied());
        let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        let limit = OVERLAP_DEPTH * diagonal;
        let mut repaired: Vec<((usize, usize), f64)> = Vec::new();
        for attempt in 0..=OVERLAP_REPAIRS {
            self.cut_small_loops();
            let pairs = self.overlapping_pairs(path)?;
            if pairs.is_empty() {
                break;
            }
            for &((r1, r2), at) in &pairs {
                let depth = self.overlap_depth(r1, r2).max(self.overlap_depth(r2, r1));
                if depth > limit {
                    let (l1, l2) = (&self.regions[r1].label, &self.regions[r2].label);
                    return Err(Error::Format {
                        path: path.to_string(),
                        msg: format!(
                            "{l1} overlaps {l2}: their edges cross near ({}, {})",
                            at[0], at[1]
                        ),
                    });
                }
                match repaired.iter_mut().find(|(k, _)| *k == (r1, r2)) {
                    Some((_, d)) => *d = d.max(depth),
                    None => repaired.push(((r1, r2), depth)),
                }
            }
            if attempt == OVERLAP_REPAIRS {
                let names: Vec<String> = pairs
                    .iter()
                    .map(|((r1, r2), _)| {
                        format!(
                            "{} and {}",
                            self.regions[*r1].label, self.regions[*r2].label
                        )
                    })
                    .collect();
                self.warnings.push(format!(
                    "{}: their borders overlap slightly and could not be made to meet; left \
                     as they are",
                    names.join("; ")
                ));
                return Ok(());
            }
            for &((r1, r2), _) in &pairs {
                self.snap_overlap(r1, r2, tol);
                self.snap_overlap(r2, r1, tol);
            }
            self.drop_repeats(tol);
            self.split_t_junctions(tol, 0.0);
        }
        for ((r1, r2), depth) in repaired {
            let (l1, l2) = (&self.regions[r1].label, &self.regions[r2].label);
            self.warnings.push(format!(
                "{l1} and {l2}: their borders overlapped slightly (by up to {:.2e} of the \
                 map's diagonal); the vertices of each inside the other were moved onto the \
                 other's border",
                depth / diagonal
            ));
        }
        Ok(())
    }

    /// The pairs of regions whose edges cross, each with where they first do. Errors: a
    /// region whose boundary crosses itself.
    fn overlapping_pairs(&self, path: &str) -> Result<Vec<Overlap>> {
        let edges = self.edges();
        let pts = &self.points;
        let segments: Vec<[[f64; 2]; 2]> =
            edges.iter().map(|([a, b], _)| [pts[*a], pts[*b]]).collect();
        let mut pairs: Vec<Overlap> = Vec::new();
        for (i, j) in proper_crossings(&segments) {
            let at = crossing_point(segments[i], segments[j]);
            let (owners, other) = (&edges[i].1, &edges[j].1);
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
        Ok(pairs)
    }

    /// Moves every vertex of region `a` lying inside region `b` to the nearest point of `b`'s
    /// boundary; when that point is within `tol` of a vertex of `b`, the vertex of `a` is
    /// replaced by it.
    fn snap_overlap(&mut self, a: usize, b: usize, tol: f64) {
        let pts = &self.points;
        let rings_b: Vec<&Vec<usize>> = self.regions[b].polygons.iter().flatten().collect();
        let coords_b: Vec<Vec<[f64; 2]>> = rings_b
            .iter()
            .map(|r| r.iter().map(|&v| pts[v]).collect())
            .collect();
        let mut verts: Vec<usize> = self.regions[a]
            .polygons
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect();
        verts.sort_unstable();
        verts.dedup();
        let mut moves: Vec<(usize, [f64; 2])> = Vec::new();
        let mut merges: HashMap<usize, usize> = HashMap::new();
        for v in verts {
            let p = pts[v];
            if coords_b.iter().filter(|r| inside_ring(p, r)).count() % 2 == 0 {
                continue;
            }
            let mut best = (f64::INFINITY, p, usize::MAX);
            for (ring, coords) in rings_b.iter().zip(&coords_b) {
                for i in 0..coords.len() {
                    let k = (i + 1) % coords.len();
                    let q = closest_point(p, coords[i], coords[k]);
                    let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                    if d < best.0 {
                        let near = |w: [f64; 2]| (w[0] - q[0]).hypot(w[1] - q[1]) <= tol;
                        let vertex = if near(coords[i]) {
                            ring[i]
                        } else if near(coords[k]) {
                            ring[k]
                        } else {
                            usize::MAX
                        };
                        best = (d, q, vertex);
                    }
                }
            }
            match best {
                (d, _, _) if d == 0.0 || !d.is_finite() => {}
                (_, _, w) if w != usize::MAX => {
                    if w != v {
                        merges.insert(v, w);
                    }
                }
                (_, q, _) => moves.push((v, q)),
            }
        }
        for (v, q) in moves {
            self.points[v] = q;
        }
        if !merges.is_empty() {
            for v in self
                .regions
                .iter_mut()
                .flat_map(|r| r.polygons.iter_mut().flatten().flatten())
            {
                if let Some(&w) = merges.get(v) {
                    *v = w;
                }
            }
        }
    }

    /// Removes from every ring the vertices repeating the one before and the zero-width
    /// spikes that merges may leave (see [`remove_spikes`]).
    fn drop_repeats(&mut self, tol: f64) {
        let points = &self.points;
        for ring in self
            .regions
            .iter_mut()
            .flat_map(|r| r.polygons.iter_mut().flatten())
        {
            ring.dedup();
            while ring.len() > 1 && ring.first() == ring.last() {
                ring.pop();
            }
            remove_spikes(ring, points, tol);
        }
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
