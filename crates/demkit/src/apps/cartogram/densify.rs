//! Extra vertices on long edges, so that the straight edges between moved vertices follow the
//! curved image of each edge. An edge shared by two rings gets the same new vertices on both
//! sides: they are computed once per undirected edge, from its lower-numbered end.

use super::raster::IndexRings;
use std::collections::{HashMap, HashSet};

/// The most vertices one edge may get in one call.
const MAX_SPLIT: usize = 4096;

/// Splits every ring edge of `regions` longer than `max_len` into equal parts no longer than
/// it, appending the new vertices to `points`. Returns how many were added.
pub fn densify(points: &mut Vec<[f64; 2]>, regions: &mut [IndexRings], max_len: f64) -> usize {
    if !(max_len > 0.0) {
        return 0;
    }
    subdivide(points, regions, |_, len| {
        if len > max_len {
            (len / max_len).ceil() as usize
        } else {
            1
        }
    })
}

/// Splits each of the undirected `edges` (`[lower, higher]` vertex indices) of `regions` into
/// `parts` equal parts, appending the new vertices to `points`. Returns how many were added.
pub fn split_edges(
    points: &mut Vec<[f64; 2]>,
    regions: &mut [IndexRings],
    edges: &HashSet<[usize; 2]>,
    parts: usize,
) -> usize {
    subdivide(points, regions, |edge, _| {
        if edges.contains(&edge) { parts } else { 1 }
    })
}

/// Splits every ring edge into the number of equal parts `parts(edge, length)` asks for
/// (1: kept; at most [`MAX_SPLIT`]), with the edge as `[lower, higher]` vertex indices.
fn subdivide(
    points: &mut Vec<[f64; 2]>,
    regions: &mut [IndexRings],
    parts: impl Fn([usize; 2], f64) -> usize,
) -> usize {
    let before = points.len();
    let mut inner: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for ring in regions.iter_mut().flatten().flatten() {
        let n = ring.len();
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            out.push(a);
            let (lo, hi) = (a.min(b), a.max(b));
            let (p, q) = (points[lo], points[hi]);
            let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            let count = parts([lo, hi], len).min(MAX_SPLIT);
            if count < 2 {
                continue;
            }
            let mid = inner.entry((lo, hi)).or_insert_with(|| {
                (1..count)
                    .map(|k| {
                        let f = k as f64 / count as f64;
                        points.push([p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])]);
                        points.len() - 1
                    })
                    .collect()
            });
            if a == lo {
                out.extend(mid.iter().copied());
            } else {
                out.extend(mid.iter().rev().copied());
            }
        }
        *ring = out;
    }
    points.len() - before
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_edges_get_the_same_vertices_in_opposite_orders() {
        let mut pts = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [2.0, 0.0],
            [2.0, 1.0],
        ];
        let mut regions = vec![vec![vec![vec![0, 1, 2, 3]]], vec![vec![vec![1, 4, 5, 2]]]];
        let added = densify(&mut pts, &mut regions, 0.6);
        assert_eq!(added, 7);
        let a = &regions[0][0][0];
        let b = &regions[1][0][0];
        // Edge 1–2: one vertex, used by both.
        let ia = a.iter().position(|&v| v == 1).unwrap();
        let ib = b.iter().position(|&v| v == 2).unwrap();
        assert_eq!(a[ia + 1], b[ib + 1]);
        assert_eq!(pts[a[ia + 1]], [1.0, 0.5]);
    }

    #[test]
    fn only_the_edges_asked_for_are_split() {
        let mut pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mut regions = vec![vec![vec![vec![0, 1, 2, 3]]]];
        let edges: HashSet<[usize; 2]> = [[0, 3]].into_iter().collect();
        assert_eq!(split_edges(&mut pts, &mut regions, &edges, 4), 3);
        // The ring runs 3 → 0, so the new vertices come in reverse order.
        assert_eq!(regions[0][0][0], vec![0, 1, 2, 3, 6, 5, 4]);
        assert_eq!(pts[4], [0.0, 0.25]);
    }
}
