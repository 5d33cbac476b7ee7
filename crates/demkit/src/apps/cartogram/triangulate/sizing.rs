//! The graded spacing of the cartogram mesh outside the small polygons' own lattices: a
//! quadtree of cells whose sides shrink towards the small polygons and grow back to the base
//! spacing (see the parent module).

use super::{GRADING_RING, Ground, HALO, MAX_LEVEL, distance};
use std::collections::HashSet;
use std::hash::{BuildHasherDefault, Hasher};

/// A hash for cell keys (two 32-bit indices in one `u64`): one multiply, deterministic.
#[derive(Default)]
struct CellHash(u64);

impl Hasher for CellHash {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

type CellSet = HashSet<u64, BuildHasherDefault<CellHash>>;

fn key(i: i64, j: i64) -> u64 {
    ((i as u64) << 32) | (j as u64 & 0xffff_ffff)
}

fn unkey(k: u64) -> (i64, i64) {
    ((k >> 32) as i64, (k & 0xffff_ffff) as i64)
}

/// The graded spacing outside the small polygons' own lattices, as a quadtree. Level ℓ has
/// square cells of side `h / 2^ℓ` indexed from the frame's lower corner; every level-0 cell
/// exists, and a cell of level ℓ > 0 exists when its parent is split. The cells a small
/// polygon's rings pass through exist at the level whose side is at most [`HALO`] times its
/// spacing `s` (at most [`MAX_LEVEL`]); around every cell that exists at level ℓ, the cells of level
/// ℓ − 1 within [`GRADING_RING`] exist too, which grades the spacing back to `h`. The spacing
/// at a point is the side of the leaf cell containing it. The work is proportional to the
/// cells along the rings.
pub(super) struct Sizing {
    lo: [f64; 2],
    h: f64,
    /// Level-0 cells along x and y.
    n: [i64; 2],
    /// `split[ℓ]`: the cells of level ℓ that are divided into four (none at [`MAX_LEVEL`]).
    split: Vec<CellSet>,
}

impl Sizing {
    pub(super) fn new(ground: &Ground, spacing: &[Option<f64>], h: f64) -> Self {
        let (lo, hi) = (ground.lo, ground.hi);
        let n = [
            (((hi[0] - lo[0]) / h).ceil() as i64).max(1),
            (((hi[1] - lo[1]) / h).ceil() as i64).max(1),
        ];
        let mut sizing = Sizing {
            lo,
            h,
            n,
            split: vec![CellSet::default(); MAX_LEVEL + 1],
        };
        let pts = &ground.set.points;
        // The cells each small polygon's rings pass through, by level.
        let mut wanted: Vec<CellSet> = vec![CellSet::default(); MAX_LEVEL + 1];
        for (piece, s) in ground.pieces.iter().zip(spacing) {
            let Some(s) = *s else { continue };
            let level = ((h / (HALO * s)).log2().ceil().max(0.0) as usize).min(MAX_LEVEL);
            if level == 0 {
                continue;
            }
            let step = 0.5 * sizing.side(level);
            for ring in &piece.rings {
                for i in 0..ring.len() {
                    let (p, q) = (pts[ring[i]], pts[ring[(i + 1) % ring.len()]]);
                    let m = (distance(p, q) / step).ceil().max(1.0) as usize;
                    for t in 0..=m {
                        let u = t as f64 / m as f64;
                        let x = [p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1])];
                        let (ci, cj) = sizing.cell(x, level);
                        wanted[level].insert(key(ci, cj));
                    }
                }
            }
        }
        // Grading, from the finest level up: a cell that exists needs its parent and the
        // parent's neighbours within the ring.
        for l in (1..=MAX_LEVEL).rev() {
            let mut cells: Vec<u64> = wanted[l].iter().copied().collect();
            cells.sort_unstable();
            let (nx, ny) = (n[0] << (l - 1), n[1] << (l - 1));
            for c in cells {
                let (i, j) = unkey(c);
                let (pi, pj) = (i >> 1, j >> 1);
                sizing.split[l - 1].insert(key(pi, pj));
                if l >= 2 {
                    for di in -GRADING_RING..=GRADING_RING {
                        for dj in -GRADING_RING..=GRADING_RING {
                            let (qi, qj) = (pi + di, pj + dj);
                            if (0..nx).contains(&qi) && (0..ny).contains(&qj) {
                                wanted[l - 1].insert(key(qi, qj));
                            }
                        }
                    }
                }
            }
        }
        sizing
    }

    /// The side of the cells of level `l`.
    fn side(&self, l: usize) -> f64 {
        self.h / (1u64 << l) as f64
    }

    /// The cell of level `l` containing `p` (clamped to the frame).
    fn cell(&self, p: [f64; 2], l: usize) -> (i64, i64) {
        let s = self.side(l);
        let lim = |m: i64| (m << l) - 1;
        (
            (((p[0] - self.lo[0]) / s).floor() as i64).clamp(0, lim(self.n[0])),
            (((p[1] - self.lo[1]) / s).floor() as i64).clamp(0, lim(self.n[1])),
        )
    }

    /// The spacing wanted at `p`: the side of the leaf cell containing it.
    pub(super) fn at(&self, p: [f64; 2]) -> f64 {
        for l in 0..MAX_LEVEL {
            let (i, j) = self.cell(p, l);
            if !self.split[l].contains(&key(i, j)) {
                return self.side(l);
            }
        }
        self.side(MAX_LEVEL)
    }

    /// The leaf cells finer than the base spacing, as (centre, side), in a fixed order.
    pub(super) fn fine_cells(&self) -> Vec<([f64; 2], f64)> {
        let mut out = Vec::new();
        for l in 1..=MAX_LEVEL {
            let s = self.side(l);
            let mut parents: Vec<u64> = self.split[l - 1].iter().copied().collect();
            parents.sort_unstable();
            for p in parents {
                let (pi, pj) = unkey(p);
                for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (i, j) = (2 * pi + di, 2 * pj + dj);
                    if !self.split[l].contains(&key(i, j)) {
                        let c = [
                            self.lo[0] + (i as f64 + 0.5) * s,
                            self.lo[1] + (j as f64 + 0.5) * s,
                        ];
                        out.push((c, s));
                    }
                }
            }
        }
        out
    }
}
