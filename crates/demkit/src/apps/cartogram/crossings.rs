//! Which segments of a set cross each other properly: the one crossing test behind reading
//! (overlapping or self-crossing regions), the flow's rounds (edges to refine) and the output
//! check ([`super::validity`]).

use super::buckets::Buckets;
use super::raster::IndexRings;
use super::rings::{bbox, orient};
use std::collections::HashSet;

/// Every pair `(i, j)`, `i < j`, of `segments` that cross properly: they share no end
/// position, and each has its ends strictly on both sides of the other's line. Segments are
/// bucketed by their bounding boxes, so the cost grows with the segments and their overlaps,
/// not with their square.
pub(crate) fn proper_crossings(segments: &[[[f64; 2]; 2]]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    if segments.is_empty() {
        return out;
    }
    let (lo, hi) = bbox(segments.iter().flatten().copied());
    let boxed = |[a, b]: &[[f64; 2]; 2]| {
        (
            [a[0].min(b[0]), a[1].min(b[1])],
            [a[0].max(b[0]), a[1].max(b[1])],
        )
    };
    let boxes: Vec<([f64; 2], [f64; 2])> = segments.iter().map(boxed).collect();
    let grid = Buckets::new(lo, hi, &boxes);
    let mut seen = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        let (l, h) = boxed(s);
        seen.clear();
        grid.visit(l, h, |j| {
            if j > i {
                seen.push(j);
            }
        });
        seen.sort_unstable();
        seen.dedup();
        let [a, b] = *s;
        for &j in &seen {
            let [c, d] = segments[j];
            if a == c || a == d || b == c || b == d {
                continue;
            }
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
                out.push((i, j));
            }
        }
    }
    out
}

/// Where the segments `s` and `t`, which cross, meet.
pub(crate) fn crossing_point(s: [[f64; 2]; 2], t: [[f64; 2]; 2]) -> [f64; 2] {
    let (o1, o2) = (orient(s[0], s[1], t[0]), orient(s[0], s[1], t[1]));
    let f = if o1 != o2 { o1 / (o1 - o2) } else { 0.5 };
    [
        t[0][0] + f * (t[1][0] - t[0][0]),
        t[0][1] + f * (t[1][1] - t[0][1]),
    ]
}

/// The undirected ring edges (`[lower, higher]` vertex indices) of `regions` over `points`
/// that cross another edge properly.
pub(crate) fn crossing_edges(points: &[[f64; 2]], regions: &[IndexRings]) -> HashSet<[usize; 2]> {
    let mut seen = HashSet::new();
    let mut edges = Vec::new();
    for ring in regions.iter().flatten().flatten() {
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            let e = [a.min(b), a.max(b)];
            if a != b && seen.insert(e) {
                edges.push(e);
            }
        }
    }
    let segments: Vec<[[f64; 2]; 2]> = edges
        .iter()
        .map(|[a, b]| [points[*a], points[*b]])
        .collect();
    proper_crossings(&segments)
        .into_iter()
        .flat_map(|(i, j)| [edges[i], edges[j]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_touching_and_parallel_segments() {
        let segments = [
            [[0.0, 0.0], [2.0, 2.0]],
            [[0.0, 2.0], [2.0, 0.0]], // crosses 0 at (1, 1)
            [[2.0, 2.0], [3.0, 0.0]], // shares an end with 0
            [[0.0, 0.5], [2.0, 2.5]], // parallel to 0
            [[1.0, 1.0], [1.0, 0.2]], // ends on 0 and 1: not proper
        ];
        assert_eq!(proper_crossings(&segments), vec![(0, 1), (1, 3)]);
        assert_eq!(crossing_point(segments[0], segments[1]), [1.0, 1.0]);
    }
}
