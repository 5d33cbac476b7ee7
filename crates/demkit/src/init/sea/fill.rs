//! The lattice points filling the gap between the ROI and the unit circle (DEM paper
//! Algorithm 4, step 2), graded by distance to the ROI boundary.

use super::boundary_index::BoundaryIndex;

/// Most lattice points allowed in the unit disk; beyond that the lattice is coarsened.
pub(super) const MAX_FILL_POINTS: f64 = 4.0e6;

/// The lattice spacing: the mean edge length l, but not so small that the hexagonal lattice
/// (2/(√3 l²) points per unit area) would exceed [`MAX_FILL_POINTS`] in the unit disk, and not
/// larger than a quarter of the disk's radius.
pub(super) fn fill_spacing(l: f64) -> f64 {
    let min = (2.0 * std::f64::consts::PI / (3f64.sqrt() * MAX_FILL_POINTS)).sqrt();
    if l.is_finite() {
        l.clamp(min, 0.25)
    } else {
        0.25
    }
}

/// How many lattice spacings each band of the graded fill is wide before the spacing doubles.
pub(super) const BAND_WIDTH: f64 = 3.0;

/// The distance bands of the graded fill: level `k` has lattice spacing `s·2^k` and covers the
/// points whose distance to the ROI boundary lies in `[lo_k, hi_k)`, with `lo_0 = s/2`,
/// `hi_k = lo_k + BAND_WIDTH·s·2^k` and a gap of a quarter spacing between bands (no two points
/// of neighbouring levels come closer than that). The last level, the first whose spacing
/// reaches 0.25, has no upper limit. Near the ROI the sea is as fine as the ROI's own mesh; far
/// from it, where the density is uniform, it coarsens geometrically — the sea then costs a
/// multiple of the ROI's boundary length instead of a multiple of the disk's area.
pub(super) struct Bands<'a> {
    /// Per level: spacing, index answering "distance ≥ lo", index answering "distance ≥ hi"
    /// (`None` for the last level).
    levels: Vec<(f64, BoundaryIndex<'a>, Option<BoundaryIndex<'a>>)>,
}

impl<'a> Bands<'a> {
    pub(super) fn new(poly: &'a [[f64; 2]], s: f64) -> Self {
        let mut levels = Vec::new();
        let (mut spacing, mut lo) = (s, 0.5 * s);
        loop {
            let last = spacing >= 0.25 || levels.len() >= 16;
            let hi = lo + BAND_WIDTH * spacing;
            let upper = (!last).then(|| BoundaryIndex::new(poly, hi));
            levels.push((spacing, BoundaryIndex::new(poly, lo), upper));
            if last {
                break;
            }
            spacing *= 2.0;
            lo = hi + 0.25 * spacing;
        }
        Self { levels }
    }

    /// The spacing wanted at `p` (outside the ROI): that of the finest level whose band
    /// reaches `p`.
    pub(super) fn spacing_at(&self, p: [f64; 2]) -> f64 {
        for (spacing, _, upper) in &self.levels {
            match upper {
                Some(u) if u.far_from_boundary(p) => continue,
                _ => return *spacing,
            }
        }
        self.levels.last().map_or(0.25, |l| l.0)
    }
}

/// Points on the unit circle, counter-clockwise from (1, 0), each at the local spacing of the
/// graded fill ([`Bands::spacing_at`]) from the previous one.
pub(super) fn circle_points(bands: &Bands) -> Vec<[f64; 2]> {
    let tau = 2.0 * std::f64::consts::PI;
    let mut angles: Vec<f64> = vec![0.0];
    loop {
        let t = *angles.last().unwrap_or(&0.0);
        let step = bands.spacing_at([t.cos(), t.sin()]).min(tau / 8.0);
        if t + 1.5 * step > tau {
            break;
        }
        angles.push(t + step);
    }
    angles.iter().map(|t| [t.cos(), t.sin()]).collect()
}

/// The graded fill of the gap between the ROI and the unit circle: for every level of
/// `bands`, the hexagonal lattice points of its spacing `s` in |z| ≤ 1 − s/2 that lie outside
/// the ROI polygon and in the level's distance band.
pub(super) fn graded_fill(index: &BoundaryIndex, bands: &Bands) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for (s, lower, upper) in &bands.levels {
        lattice_points(*s, |p| {
            if lower.far_from_boundary(p)
                && upper.as_ref().is_none_or(|u| !u.far_from_boundary(p))
                && !index.contains(p)
            {
                out.push(p);
            }
        });
    }
    out
}

/// Calls `keep` with every point of the hexagonal lattice of spacing `s` in |z| ≤ 1 − s/2.
pub(super) fn lattice_points(s: f64, mut keep: impl FnMut([f64; 2])) {
    let dy = s * 3f64.sqrt() / 2.0;
    let rmax = 1.0 - 0.5 * s;
    let rows = (rmax / dy).floor() as i64;
    let cols = (rmax / s).ceil() as i64 + 1;
    for j in -rows..=rows {
        let y = j as f64 * dy;
        let shift = if j.rem_euclid(2) == 1 { 0.5 * s } else { 0.0 };
        for i in -cols..=cols {
            let x = i as f64 * s + shift;
            if x * x + y * y <= rmax * rmax {
                keep([x, y]);
            }
        }
    }
}
