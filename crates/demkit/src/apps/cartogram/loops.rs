//! Small loops of a ring crossing itself, cut off as the ring is read: quantised map files
//! (TopoJSON, coarse Natural Earth scales) leave rings that cross themselves around a few
//! vertices. The part on the far side of the crossing with the smaller area goes, the crossing
//! point joins the two sides; a loop not small against the rest is left for the refusal of
//! [`super::topology`].

use super::crossings::{crossing_point, proper_crossings};
use super::regions::RegionSet;
use super::rings::ring_area;

/// A loop is cut off when its area is at most this fraction of the rest of its ring's.
const LOOP_SHARE: f64 = 1e-2;

/// At most this many loops are cut in one map.
const MAX_CUTS: usize = 1000;

impl RegionSet {
    /// Cuts off the small loops where a ring crosses itself (see the module's description),
    /// one warning per region naming how many; returns how many were cut.
    pub(super) fn cut_small_loops(&mut self) -> usize {
        let mut cuts = vec![0usize; self.regions.len()];
        let mut total = 0;
        while total < MAX_CUTS && self.cut_one_loop(&mut cuts) {
            total += 1;
        }
        for (r, n) in cuts.into_iter().enumerate() {
            if n > 0 {
                self.warnings.push(format!(
                    "{}: its boundary crossed itself; {n} small loop{} (below {LOOP_SHARE} of the \
                     ring's area) cut off at the crossing",
                    self.regions[r].label,
                    if n == 1 { "" } else { "s" }
                ));
            }
        }
        total
    }

    /// Finds one crossing of two edges of the same ring whose smaller side is a small loop,
    /// and cuts it. Returns whether one was cut.
    fn cut_one_loop(&mut self, cuts: &mut [usize]) -> bool {
        let edges = self.edges();
        let segments: Vec<[[f64; 2]; 2]> = edges
            .iter()
            .map(|([a, b], _)| [self.points[*a], self.points[*b]])
            .collect();
        for (i, j) in proper_crossings(&segments) {
            let (e, f) = (edges[i].0, edges[j].0);
            for &r in edges[i].1.iter().filter(|r| edges[j].1.contains(r)) {
                let at = crossing_point(segments[i], segments[j]);
                if self.cut_in_region(r, e, f, at) {
                    cuts[r] += 1;
                    return true;
                }
            }
        }
        false
    }

    /// In the ring of region `r` holding both edges `e` and `f` (undirected), keeps the side
    /// of the crossing at `at` with the larger area and joins it at `at`, when the other side
    /// is small. Returns whether it did.
    fn cut_in_region(&mut self, r: usize, e: [usize; 2], f: [usize; 2], at: [f64; 2]) -> bool {
        let position = |ring: &[usize], edge: [usize; 2]| {
            (0..ring.len()).find(|&k| {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                [a.min(b), a.max(b)] == edge
            })
        };
        let x = self.points.len();
        let points = &self.points;
        for ring in self.regions[r].polygons.iter_mut().flatten() {
            let (Some(p), Some(q)) = (position(ring, e), position(ring, f)) else {
                continue;
            };
            let (p, q) = (p.min(q), p.max(q));
            // The loop: the vertices after edge p up to edge q's start; the rest wraps.
            let inner: Vec<usize> = ring[p + 1..=q].to_vec();
            let outer: Vec<usize> = ring[q + 1..].iter().chain(&ring[..=p]).copied().collect();
            let area = |side: &[usize]| {
                let mut c: Vec<[f64; 2]> = side.iter().map(|&v| points[v]).collect();
                c.push(at);
                ring_area(&c).abs()
            };
            let (a_in, a_out) = (area(&inner), area(&outer));
            let keep = if a_in <= LOOP_SHARE * a_out {
                outer
            } else if a_out <= LOOP_SHARE * a_in {
                inner
            } else {
                return false;
            };
            if keep.len() < 2 {
                return false;
            }
            let mut joined = keep;
            joined.push(x);
            *ring = joined;
            self.points.push(at);
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::super::geojson::RawRegion;
    use super::*;

    #[test]
    fn a_small_loop_is_cut_and_a_figure_eight_refused() {
        // A unit square whose top edge makes a small twisted loop: the ring runs
        // (0.6, 1) → (0.4, 1.02) → (0.4, 1) → (0.6, 1.02) → … crossing itself at (0.5, 1.01).
        let looped = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.6, 1.0],
            [0.4, 1.02],
            [0.4, 1.0],
            [0.6, 1.02],
            [0.2, 1.0],
            [0.0, 1.0],
        ];
        let raw = |ring: Vec<[f64; 2]>| RawRegion {
            label: "feature 0".into(),
            value: 1.0,
            multi: false,
            polygons: vec![vec![ring]],
        };
        let set = RegionSet::build(&[raw(looped)], "t").unwrap();
        assert!(
            set.warnings.iter().any(|w| w.contains("1 small loop")),
            "{:?}",
            set.warnings
        );
        let ring: Vec<[f64; 2]> = set.regions[0].polygons[0][0]
            .iter()
            .map(|&v| set.points[v])
            .collect();
        let segments: Vec<[[f64; 2]; 2]> = (0..ring.len())
            .map(|k| [ring[k], ring[(k + 1) % ring.len()]])
            .collect();
        assert!(proper_crossings(&segments).is_empty());
        // A bow tie's lobes are of comparable areas: no small loop.
        let eight = vec![[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 1.0]];
        let e = RegionSet::build(&[raw(eight)], "t").unwrap_err();
        assert!(e.to_string().contains("crosses itself"), "{e}");
    }
}
