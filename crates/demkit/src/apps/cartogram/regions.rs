//! The regions of a cartogram as one planar straight-line graph: every vertex stored once
//! (positions closer than a tolerance are merged, so a border shared by two regions is made of
//! the same vertices and edges on both sides), a vertex of one region lying on an edge of
//! another splits that edge (no T-junctions), and no two edges cross.
//!
//! The graph is held in a normalised frame ([`Frame`]): the input's bounding box centred at
//! the origin with its larger half-side 1, so that squares of side 1e300 or 1e-300 are
//! computed on the same numbers as unit squares and only the output is scaled back.

use super::Polygon;
use super::buckets::{Grid, SegmentGrid};
use super::geojson::RawRegion;
use crate::{Error, Result};
use std::collections::HashMap;

/// One feature's geometry as rings of indices into [`RegionSet::points`].
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// How messages name the feature (see [`super::geojson::feature_label`]).
    pub label: String,
    /// The region's value (> 0).
    pub value: f64,
    /// Whether the feature is a MultiPolygon.
    pub multi: bool,
    /// Polygons → rings (exterior first) → vertex indices, without closing vertex.
    pub polygons: Vec<Vec<Vec<usize>>>,
}

/// All regions over one shared vertex list.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionSet {
    /// The distinct vertices, in the normalised frame (see [`RegionSet::frame`]).
    pub points: Vec<[f64; 2]>,
    /// The regions, in feature order.
    pub regions: Vec<Region>,
    /// The similarity from input coordinates to those of [`RegionSet::points`].
    pub frame: Frame,
    /// What was cleaned on reading, one line per region: degenerate parts dropped, zero-width
    /// spikes removed.
    pub warnings: Vec<String>,
}

/// A similarity of the plane that takes input coordinates to a normalised frame:
/// `q = (p − centre) / scale`. Built from a bounding box, it puts the box's centre at the
/// origin and its larger half-side at 1, with every step free of overflow and underflow for
/// any finite box of positive extent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The input position that becomes the origin.
    pub centre: [f64; 2],
    /// The input length that becomes 1.
    pub scale: f64,
}

impl Frame {
    /// The identity (input coordinates are already normalised).
    pub const IDENTITY: Frame = Frame {
        centre: [0.0, 0.0],
        scale: 1.0,
    };

    /// The frame of the box `lo`–`hi` (centre at the origin, larger half-side 1), or `None`
    /// when the box is not finite or has no extent.
    pub fn of_box(lo: [f64; 2], hi: [f64; 2]) -> Option<Frame> {
        // Halves first: (hi − lo) may overflow, hi/2 − lo/2 cannot.
        let centre = [0.5 * lo[0] + 0.5 * hi[0], 0.5 * lo[1] + 0.5 * hi[1]];
        let scale = (0.5 * hi[0] - 0.5 * lo[0]).max(0.5 * hi[1] - 0.5 * lo[1]);
        (scale > 0.0 && scale.is_finite() && centre.iter().all(|c| c.is_finite()))
            .then_some(Frame { centre, scale })
    }

    /// Input coordinates → normalised ones.
    pub fn to_unit(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.centre[0]) / self.scale,
            (p[1] - self.centre[1]) / self.scale,
        ]
    }

    /// Normalised coordinates → input ones (not finite when the result lies beyond the range
    /// of `f64`).
    pub fn to_input(&self, q: [f64; 2]) -> [f64; 2] {
        [
            self.centre[0] + self.scale * q[0],
            self.centre[1] + self.scale * q[1],
        ]
    }

    /// A normalised area in input units (infinite beyond the range of `f64`, as for squares
    /// of side 1e300, whose area 1e600 has no `f64`).
    pub fn area_to_input(&self, a: f64) -> f64 {
        a * self.scale * self.scale
    }
}

/// Twice the signed area of a closed ring given without closing point, halved: positive when
/// counter-clockwise (shoelace formula).
pub fn ring_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    let mut s = 0.0;
    for i in 0..n {
        let (p, q) = (ring[i], ring[(i + 1) % n]);
        s += p[0] * q[1] - p[1] * q[0];
    }
    0.5 * s
}

/// +1 when the ring runs counter-clockwise, −1 when clockwise, 0 when its area vanishes;
/// decided on the ring moved to its first point and scaled to unit size, so that no product
/// overflows or underflows whatever the coordinates' magnitude.
pub fn ring_orientation(ring: &[[f64; 2]]) -> f64 {
    let Some(&o) = ring.first() else { return 0.0 };
    // Halved offsets cannot overflow; their largest magnitude sets the scale.
    let half: Vec<[f64; 2]> = ring
        .iter()
        .map(|p| [0.5 * p[0] - 0.5 * o[0], 0.5 * p[1] - 0.5 * o[1]])
        .collect();
    let s = half
        .iter()
        .fold(0.0f64, |m, d| m.max(d[0].abs()).max(d[1].abs()));
    if !(s > 0.0 && s.is_finite()) {
        return 0.0;
    }
    let unit: Vec<[f64; 2]> = half.iter().map(|d| [d[0] / s, d[1] / s]).collect();
    let a = ring_area(&unit);
    if a > 0.0 {
        1.0
    } else if a < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The area of a polygon (exterior minus holes, whatever the rings' orientations).
pub fn polygon_area(rings: &[Vec<[f64; 2]>]) -> f64 {
    rings
        .iter()
        .enumerate()
        .map(|(j, r)| {
            if j == 0 {
                ring_area(r).abs()
            } else {
                -ring_area(r).abs()
            }
        })
        .sum()
}

/// Relative tolerance (of the bounding box diagonal) below which two positions are the same
/// vertex, or a vertex lies on an edge.
const SNAP: f64 = 1e-9;

impl RegionSet {
    /// Builds the shared vertex graph of `raw` in its normalised frame ([`Frame::of_box`] of
    /// the regions' bounding box); `path` names the file in messages.
    ///
    /// Errors ([`Error::Format`], naming the feature and ring): all positions equal (the
    /// regions have no extent), a ring with fewer than three distinct points or zero area,
    /// edges that cross (within one region: the region's boundary crosses itself; between
    /// two: the regions overlap).
    pub fn build(raw: &[RawRegion], path: &str) -> Result<RegionSet> {
        let err = |msg: String| Error::Format {
            path: path.to_string(),
            msg,
        };
        let (lo, hi) = bbox(
            raw.iter()
                .flat_map(|r| r.polygons.iter().flatten().flatten().copied()),
        );
        let frame = Frame::of_box(lo, hi).ok_or_else(|| {
            err("the regions have no extent (all their positions are equal)".into())
        })?;
        // In the normalised frame the bounding box is [-1, 1] along its larger side.
        let (lo, hi) = (frame.to_unit(lo), frame.to_unit(hi));
        let diag = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
        let tol = SNAP * diag;
        let mut snap = Snapper::new(tol);
        let mut regions = Vec::with_capacity(raw.len());
        let mut warnings = Vec::new();
        for r in raw {
            let mut polygons = Vec::with_capacity(r.polygons.len());
            let mut dropped: Vec<String> = Vec::new();
            let mut first_refusal: Option<String> = None;
            let mut spikes = 0;
            for (k, rings) in r.polygons.iter().enumerate() {
                let mut out = Vec::with_capacity(rings.len());
                for (j, ring) in rings.iter().enumerate() {
                    let mut idx: Vec<usize> = Vec::with_capacity(ring.len());
                    for &p in ring {
                        let v = snap.insert(frame.to_unit(p));
                        if idx.last() != Some(&v) {
                            idx.push(v);
                        }
                    }
                    while idx.len() > 1 && idx.first() == idx.last() {
                        idx.pop();
                    }
                    let ring_spikes = remove_spikes(&mut idx, &snap.points, tol);
                    spikes += ring_spikes;
                    let pts: Vec<[f64; 2]> = idx.iter().map(|&v| snap.points[v]).collect();
                    let mut distinct = idx.clone();
                    distinct.sort_unstable();
                    distinct.dedup();
                    let problem = if distinct.len() < 3 && ring_spikes > 0 {
                        // A ring that was all spike: a line.
                        Some("has zero area")
                    } else if distinct.len() < 3 {
                        Some("has fewer than 3 distinct points")
                    } else if ring_area(&pts).abs() <= tol * diag {
                        Some("has zero area")
                    } else {
                        None
                    };
                    if let Some(problem) = problem {
                        first_refusal.get_or_insert(format!(
                            "{}: ring {j} of polygon {k} {problem}",
                            r.label
                        ));
                        if j == 0 {
                            dropped.push(format!("polygon {k} ({problem})"));
                            out.clear();
                            break;
                        }
                        dropped.push(format!("ring {j} of polygon {k} ({problem})"));
                        continue;
                    }
                    out.push(idx);
                }
                if !out.is_empty() {
                    polygons.push(out);
                }
            }
            if polygons.is_empty() {
                return Err(err(
                    first_refusal.unwrap_or_else(|| format!("{}: has no polygon", r.label))
                ));
            }
            if !dropped.is_empty() {
                warnings.push(format!("{}: dropped {}", r.label, dropped.join(", ")));
            }
            if spikes > 0 {
                warnings.push(format!(
                    "{}: removed {spikes} zero-width spike vertices",
                    r.label
                ));
            }
            regions.push(Region {
                label: r.label.clone(),
                value: r.value,
                multi: r.multi,
                polygons,
            });
        }
        let mut set = RegionSet {
            points: snap.points,
            regions,
            frame,
            warnings,
        };
        set.split_t_junctions(tol);
        set.check_crossings(path)?;
        set.check_holes_inside(path)?;
        Ok(set)
    }

    /// Every hole lies inside its polygon's exterior ring. With no two edges crossing (checked
    /// first), a hole is wholly inside or wholly outside, so the middle of one of its edges
    /// decides.
    fn check_holes_inside(&self, path: &str) -> Result<()> {
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

    /// The distinct undirected edges of all rings, each with the regions using it.
    pub fn edges(&self) -> Vec<([usize; 2], Vec<usize>)> {
        let mut map: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        let mut order = Vec::new();
        for (r, region) in self.regions.iter().enumerate() {
            for ring in region.polygons.iter().flatten() {
                for i in 0..ring.len() {
                    let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                    let key = [a.min(b), a.max(b)];
                    let owners = map.entry(key).or_insert_with(|| {
                        order.push(key);
                        Vec::new()
                    });
                    if !owners.contains(&r) {
                        owners.push(r);
                    }
                }
            }
        }
        order
            .into_iter()
            .map(|k| {
                let o = map.remove(&k).unwrap_or_default();
                (k, o)
            })
            .collect()
    }

    /// The vertices in input coordinates.
    pub fn input_points(&self) -> Vec<[f64; 2]> {
        self.points
            .iter()
            .map(|&p| self.frame.to_input(p))
            .collect()
    }

    /// The coordinates of every region's rings, in the normalised frame.
    pub fn coordinates(&self) -> Vec<Vec<Polygon>> {
        self.regions
            .iter()
            .map(|r| {
                r.polygons
                    .iter()
                    .map(|p| {
                        p.iter()
                            .map(|ring| ring.iter().map(|&v| self.points[v]).collect())
                            .collect()
                    })
                    .collect()
            })
            .collect()
    }

    /// Inserts into every edge the vertices lying on it (within `tol`), in order.
    fn split_t_junctions(&mut self, tol: f64) {
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
    fn check_crossings(&mut self, path: &str) -> Result<()> {
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

/// Whether `p` lies inside the closed polygon `ring` (even–odd rule).
pub(crate) fn inside_ring(p: [f64; 2], ring: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Orientation of `c` with respect to the line `a → b` (positive: left).
pub(crate) fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Regions whose borders cross are read when no vertex of one lies deeper inside the other
/// than this fraction of the map's diagonal (the slivers of unshared borders), and refused as
/// overlapping otherwise.
const OVERLAP_DEPTH: f64 = 2e-3;

/// The distance from `p` to the segment `a`–`b`.
pub(crate) fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// A ring turning back by an angle within this sine of 180° has a zero-width spike there.
const SPIKE_SINE: f64 = 1e-3;

/// Removes from a closed ring (no closing repetition) every vertex where the ring turns back
/// on itself along a line (a zero-width spike: the vertex lies within `tol` of the line
/// through its neighbours, or the turn is within [`SPIKE_SINE`] of 180°, and the ring
/// reverses there), and a vertex whose neighbours are the
/// same; repeats until none is left. Returns how many vertices were removed.
fn remove_spikes(ring: &mut Vec<usize>, points: &[[f64; 2]], tol: f64) -> usize {
    let mut removed = 0;
    let mut changed = true;
    while changed && ring.len() >= 3 {
        changed = false;
        let mut i = 0;
        while i < ring.len() && ring.len() >= 3 {
            let n = ring.len();
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            let u = [pb[0] - pa[0], pb[1] - pa[1]];
            let w = [pc[0] - pb[0], pc[1] - pb[1]];
            let cross = u[0] * w[1] - u[1] * w[0];
            let dot = u[0] * w[0] + u[1] * w[1];
            let (lu, lw) = (u[0].hypot(u[1]), w[0].hypot(w[1]));
            let thin = cross.abs() <= (tol * lu.max(lw)).max(SPIKE_SINE * lu * lw);
            if a == c || (dot < 0.0 && thin) {
                ring.remove(i);
                removed += 1;
                changed = true;
                // The neighbours may now repeat.
                let n = ring.len();
                if n >= 2 {
                    let prev = (i + n - 1) % n;
                    if ring[prev] == ring[i % n] {
                        ring.remove(i % n);
                        removed += 1;
                    }
                }
                i = i.saturating_sub(1);
            } else {
                i += 1;
            }
        }
    }
    removed
}

pub(super) fn min2(a: [f64; 2], b: [f64; 2], pad: f64) -> [f64; 2] {
    [a[0].min(b[0]) + pad, a[1].min(b[1]) + pad]
}

pub(super) fn max2(a: [f64; 2], b: [f64; 2], pad: f64) -> [f64; 2] {
    [a[0].max(b[0]) + pad, a[1].max(b[1]) + pad]
}

/// Bounding box of points.
pub(crate) fn bbox(points: impl Iterator<Item = [f64; 2]>) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Merges positions closer than a tolerance (hash of cells of the tolerance's size).
struct Snapper {
    tol: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    points: Vec<[f64; 2]>,
}

impl Snapper {
    fn new(tol: f64) -> Self {
        Self {
            tol,
            cells: HashMap::new(),
            points: Vec::new(),
        }
    }

    /// The index of `p`, or of a stored point within the tolerance of it.
    fn insert(&mut self, p: [f64; 2]) -> usize {
        let c = (
            (p[0] / self.tol).floor() as i64,
            (p[1] / self.tol).floor() as i64,
        );
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = self.cells.get(&(c.0 + dx, c.1 + dy)) {
                    for &v in list {
                        let q = self.points[v];
                        if (q[0] - p[0]).abs() <= self.tol && (q[1] - p[1]).abs() <= self.tol {
                            return v;
                        }
                    }
                }
            }
        }
        self.points.push(p);
        let v = self.points.len() - 1;
        self.cells.entry(c).or_default().push(v);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(label: &str, polygons: Vec<Polygon>) -> RawRegion {
        RawRegion {
            label: label.into(),
            value: 1.0,
            multi: polygons.len() > 1,
            polygons,
        }
    }

    fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s], [x, y]]
    }

    #[test]
    fn shared_borders_share_vertices_and_t_junctions_are_split() {
        // A 2×1 block on the left of two unit squares: its right edge (2 units long) carries
        // the squares' common corner (1, 1) as a T-junction.
        let left = vec![vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 0.0],
        ]];
        let a = vec![square(1.0, 0.0, 1.0)];
        let b = vec![square(1.0, 1.0, 1.0)];
        let set = RegionSet::build(
            &[raw("L", vec![left]), raw("A", vec![a]), raw("B", vec![b])],
            "t",
        )
        .unwrap();
        // Distinct positions only: 4 (left) + 2 + 2 (the squares' right corners) + (1,1).
        assert_eq!(set.points.len(), 8);
        assert_eq!(
            set.regions[0].polygons[0][0].len(),
            5,
            "(1,1) inserted in the left ring"
        );
        let edges = set.edges();
        let shared = edges.iter().filter(|(_, o)| o.len() == 2).count();
        assert_eq!(shared, 3);
        let coords = set.coordinates();
        let total: f64 = coords.iter().flatten().map(|p| polygon_area(p)).sum();
        assert!((total - 4.0).abs() < 1e-12);
    }

    #[test]
    fn a_hole_outside_its_exterior_ring_is_refused() {
        let outer = square(0.0, 0.0, 4.0)[..4].to_vec();
        let away = square(10.0, 10.0, 1.0)[..4].to_vec();
        let e = RegionSet::build(&[raw("feature 3", vec![vec![outer.clone(), away]])], "t")
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("feature 3: ring 1 of polygon 0 (a hole) lies outside"),
            "{e}"
        );
        let inner = square(1.0, 1.0, 1.0)[..4].to_vec();
        assert!(RegionSet::build(&[raw("feature 3", vec![vec![outer, inner]])], "t").is_ok());
    }

    #[test]
    fn crossings_and_degenerate_rings_are_refused() {
        let bow = vec![vec![[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 1.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![bow])], "t").unwrap_err();
        assert!(
            e.to_string()
                .contains("feature 0: its boundary crosses itself"),
            "{e}"
        );
        let a = vec![square(0.0, 0.0, 1.0)];
        let b = vec![square(0.5, 0.5, 1.0)];
        let e = RegionSet::build(&[raw("feature 0", vec![a]), raw("feature 1", vec![b])], "t")
            .unwrap_err();
        assert!(
            e.to_string().contains("feature 0 overlaps feature 1"),
            "{e}"
        );
        let line = vec![vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 0.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![line])], "t").unwrap_err();
        assert!(e.to_string().contains("zero area"), "{e}");
        let two = vec![vec![[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![two])], "t").unwrap_err();
        assert!(
            e.to_string().contains("fewer than 3 distinct points"),
            "{e}"
        );
    }

    #[test]
    fn extreme_scales_are_normalised_and_orientations_kept() {
        for k in [1e300, 1e-300, 1e-310] {
            let sq: Vec<[f64; 2]> = square(3.0 * k, -2.0 * k, k)[..4].to_vec();
            let set = RegionSet::build(&[raw("feature 0", vec![vec![sq.clone()]])], "t").unwrap();
            // The box [-1, 1]², and back to the input, within rounding.
            let (lo, hi) = bbox(set.points.iter().copied());
            let near = |a: [f64; 2], b: f64| (a[0] - b).abs() < 1e-12 && (a[1] - b).abs() < 1e-12;
            assert!(near(lo, -1.0) && near(hi, 1.0), "{k:e}: {lo:?} {hi:?}");
            for (p, q) in set.input_points().iter().zip(&sq) {
                let tol = 1e-14 * k + 4.0 * f64::from_bits(1); // a few units of the last place
                assert!(
                    (p[0] - q[0]).abs() <= tol && (p[1] - q[1]).abs() <= tol,
                    "{p:?} {q:?}"
                );
            }
            assert_eq!(ring_orientation(&sq), 1.0, "{k:e}");
            let mut cw = sq.clone();
            cw.reverse();
            assert_eq!(ring_orientation(&cw), -1.0, "{k:e}");
        }
        // Coordinates near the largest f64: the frame's centre and scale stay finite.
        let f = Frame::of_box([-1.7e308, -1.0], [1.7e308, 1.0]).unwrap();
        assert_eq!(f.to_unit([1.7e308, 0.0]), [1.0, 0.0]);
        assert!(Frame::of_box([1.0, 1.0], [1.0, 1.0]).is_none());
        let e = RegionSet::build(&[raw("feature 0", vec![vec![vec![[2.0, 2.0]; 4]]])], "t");
        assert!(e.unwrap_err().to_string().contains("no extent"));
    }

    #[test]
    fn polygon_area_subtracts_holes_whatever_their_orientation() {
        let outer = square(0.0, 0.0, 3.0)[..4].to_vec();
        let mut hole = square(1.0, 1.0, 1.0)[..4].to_vec();
        assert_eq!(polygon_area(&[outer.clone(), hole.clone()]), 8.0);
        hole.reverse();
        assert_eq!(polygon_area(&[outer, hole]), 8.0);
    }
}
