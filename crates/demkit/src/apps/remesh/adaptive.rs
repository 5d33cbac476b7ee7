//! Points with a varying spacing in a planar region, for maps that equalize the density only
//! roughly: where the map gives a region less area than its population asks for, points must be
//! closer there for the surface to get the vertex density the population asks for (DEM paper
//! §6.2: "more points will lie on that part"). A greedy Poisson-disk selection among a fine
//! hexagonal lattice of candidates, visited in a fixed pseudo-random order, keeps a candidate
//! when no kept point is nearer than the smaller of their two spacings.

use super::region::Region;
use super::sampling::{dist, hex_rows};
use crate::geometry::grid::GridCells;

/// The radius of a greedy Poisson-disk set with the density of a hexagonal lattice of spacing
/// `s` is about this times `s` (random sequential packing covers about 55 % of the plane).
pub const RADIUS_PER_SPACING: f64 = 0.78;

/// Candidates lie on a hexagonal lattice this many times the smallest radius apart.
const CANDIDATE_STEP: f64 = 0.3;

/// The candidates of a region: points, their spacing factor and the visiting order.
pub struct Candidates {
    points: Vec<[f64; 2]>,
    /// `1 / √r` at every candidate, `r` the relative density asked for there.
    factor: Vec<f64>,
    order: Vec<usize>,
    min_factor: f64,
    max_factor: f64,
}

impl Candidates {
    /// Candidates inside `region` (of area `area`) for spacings down to `h_min · min factor`,
    /// where `relative(p)` is the density asked for at `p` relative to the mean (clamped to
    /// `[1/64, 64]`; 1 where it is unknown); at most about `max_count` of them (the densest
    /// spots then get somewhat fewer points than asked for).
    pub fn new(
        region: &Region,
        area: f64,
        h_min: f64,
        relative: &dyn Fn([f64; 2]) -> Option<f64>,
        max_count: usize,
    ) -> Self {
        let (lo, hi) = region.bounds();
        let probe = |p: [f64; 2]| {
            1.0 / relative(p)
                .filter(|r| r.is_finite() && *r > 0.0)
                .unwrap_or(1.0)
                .clamp(1.0 / 64.0, 64.0)
                .sqrt()
        };
        // A first pass on a coarse lattice finds the smallest spacing factor.
        let mut min_factor = f64::INFINITY;
        for (y, xs) in hex_rows(lo, hi, h_min) {
            for x in xs {
                min_factor = min_factor.min(probe([x, y]));
            }
        }
        if !min_factor.is_finite() {
            min_factor = 1.0;
        }
        let fewest = (2.0 * area / (3f64.sqrt() * max_count.max(1) as f64)).sqrt();
        let step = (CANDIDATE_STEP * RADIUS_PER_SPACING * h_min * min_factor).max(fewest);
        let points = region.lattice_inside(step);
        let factor: Vec<f64> = points.iter().map(|&p| probe(p).max(min_factor)).collect();
        let mut keyed: Vec<(u64, usize)> = (0..points.len()).map(|i| (mix(i as u64), i)).collect();
        keyed.sort_unstable();
        let max_factor = factor.iter().copied().fold(min_factor, f64::max);
        Candidates {
            points,
            factor,
            order: keyed.into_iter().map(|(_, i)| i).collect(),
            min_factor,
            max_factor,
        }
    }

    /// The kept points for spacing `h` (local spacing `h · factor`), at least
    /// `margin · h · factor` from the boundary of `region`.
    pub fn select(&self, region: &Region, h: f64, margin: f64) -> Vec<[f64; 2]> {
        let cell = RADIUS_PER_SPACING * h * self.min_factor;
        let (lo, hi) = region.bounds();
        let dims = [0, 1].map(|d| ((hi[d] - lo[d]) / cell).floor() as usize + 1);
        if dims[0].saturating_mul(dims[1]) > 50_000_000 {
            return Vec::new();
        }
        let reach = (self.max_factor / self.min_factor).ceil() as isize;
        let mut grid: Vec<Vec<u32>> = vec![Vec::new(); dims[0] * dims[1]];
        let mut kept: Vec<[f64; 2]> = Vec::new();
        let mut kept_radius: Vec<f64> = Vec::new();
        let cells = GridCells::new(lo, [cell; 2], dims);
        let cell_of = |p: [f64; 2]| cells.cell_of(p).map(|c| c as isize);
        for &i in &self.order {
            let p = self.points[i];
            let radius = RADIUS_PER_SPACING * h * self.factor[i];
            let c = cell_of(p);
            let span = ((radius / cell).ceil() as isize).min(reach);
            // Rings of cells outwards from the candidate's own: most candidates are turned down
            // by a point next to them.
            let mut free = true;
            'search: for ring in 0..=span {
                for dj in -ring..=ring {
                    let step = if dj.abs() == ring { 1 } else { 2 * ring.max(1) };
                    let mut di = -ring;
                    while di <= ring {
                        let (x, y) = (c[0] + di, c[1] + dj);
                        di += step;
                        if x < 0 || y < 0 || x >= dims[0] as isize || y >= dims[1] as isize {
                            continue;
                        }
                        for &k in &grid[cells.index([x as usize, y as usize])] {
                            let k = k as usize;
                            if dist(kept[k], p) < radius.min(kept_radius[k]) {
                                free = false;
                                break 'search;
                            }
                        }
                    }
                }
            }
            if !free || region.near_boundary(p, margin * h * self.factor[i]) {
                continue;
            }
            grid[cells.index([c[0] as usize, c[1] as usize])].push(kept.len() as u32);
            kept.push(p);
            kept_radius.push(radius);
        }
        kept
    }

    /// The largest spacing factor (for the region's grid).
    pub fn max_factor(&self) -> f64 {
        self.max_factor
    }
}

/// A fixed pseudo-random 64-bit mix of `x` (SplitMix64's finalizer).
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_candidates_are_capped() {
        let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let region = Region::new(&[square], 0.5);
        let c = Candidates::new(&region, 1.0, 0.01, &|_| Some(64.0), 5000);
        assert!(
            c.points.len() < 6000 && c.points.len() > 4000,
            "{}",
            c.points.len()
        );
    }

    #[test]
    fn a_denser_half_gets_more_points() {
        let square = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let region = Region::new(&[square], 0.5);
        let relative = |p: [f64; 2]| Some(if p[0] > 1.0 { 4.0 } else { 1.0 });
        let c = Candidates::new(&region, 2.0, 0.05, &relative, 1_000_000);
        let pts = c.select(&region, 0.05, 0.3);
        let right = pts.iter().filter(|p| p[0] > 1.0).count() as f64;
        let left = pts.len() as f64 - right;
        assert!(right / left > 3.0 && right / left < 5.0, "{right} / {left}");
        // About the hexagonal lattice's count on the uniform half.
        let hex = 2.0 / (3f64.sqrt() * 0.05 * 0.05);
        assert!((left / hex - 1.0).abs() < 0.25, "{left} vs {hex}");
        // No two points closer than the smaller radius.
        for (i, p) in pts.iter().enumerate() {
            for q in &pts[i + 1..] {
                assert!(dist(*p, *q) >= RADIUS_PER_SPACING * 0.025 - 1e-12);
            }
        }
    }
}
