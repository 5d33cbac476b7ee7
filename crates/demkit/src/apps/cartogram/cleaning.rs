//! Cleaning a real map's rings as they are read: positions closer than a tolerance merged into
//! one vertex ([`Snapper`]), and zero-width spikes removed ([`remove_spikes`]).

use std::collections::HashMap;

/// A ring turning back by an angle within this sine of 180° has a zero-width spike there.
const SPIKE_SINE: f64 = 1e-3;

/// Removes from a closed ring (no closing repetition) every vertex where the ring turns back
/// on itself along a line (a zero-width spike: the vertex lies within `tol` of the line
/// through its neighbours, or the turn is within [`SPIKE_SINE`] of 180°, and the ring
/// reverses there), and a vertex whose neighbours are the
/// same; repeats until none is left. Returns how many vertices were removed.
pub(super) fn remove_spikes(ring: &mut Vec<usize>, points: &[[f64; 2]], tol: f64) -> usize {
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

/// Merges positions closer than a tolerance (hash of cells of the tolerance's size).
pub(super) struct Snapper {
    tol: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    /// The distinct positions, in the order first met.
    pub(super) points: Vec<[f64; 2]>,
}

impl Snapper {
    /// An empty set of positions merged within `tol`.
    pub(super) fn new(tol: f64) -> Self {
        Self {
            tol,
            cells: HashMap::new(),
            points: Vec::new(),
        }
    }

    /// The index of `p`, or of a stored point within the tolerance of it.
    pub(super) fn insert(&mut self, p: [f64; 2]) -> usize {
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
