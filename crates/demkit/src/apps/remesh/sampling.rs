//! Near-uniform point sets on the target domains of the maps (DEM paper §6.2: "a set of
//! uniformly distributed points on the density-equalizing map"): a hexagonal lattice in the
//! plane, equally spaced points along a closed polyline, and a Fibonacci spiral on the sphere.

/// Points per unit area of a hexagonal (equilateral) lattice of spacing `h`: `2 / (√3 h²)`.
pub fn hex_density(h: f64) -> f64 {
    2.0 / (3f64.sqrt() * h * h)
}

/// The spacing of a hexagonal lattice with `n` points on area `area`: the inverse of
/// [`hex_density`].
pub fn hex_spacing(area: f64, n: usize) -> f64 {
    (2.0 * area / (3f64.sqrt() * n.max(1) as f64)).sqrt()
}

/// At most this many adjustments of the spacing to meet the requested vertex count.
const SPACING_STEPS: usize = 12;

/// The layout with closest to `n` points among those made by `layout` (for a spacing) and
/// counted by `count`: starting at spacing `h`, each step corrects the spacing by the square
/// root of the ratio of the count to `n`, until the count is within 1 % of `n` or
/// [`SPACING_STEPS`] steps have run.
pub(crate) fn fit_spacing<L>(
    mut h: f64,
    n: usize,
    layout: impl Fn(f64) -> L,
    count: impl Fn(&L) -> usize,
) -> L {
    let off = |c: usize| (c as f64 - n as f64).abs();
    let mut best: Option<L> = None;
    for _ in 0..SPACING_STEPS {
        let candidate = layout(h);
        let c = count(&candidate);
        let done = off(c) <= 0.01 * n as f64;
        if best.as_ref().is_none_or(|b| off(c) < off(count(b))) {
            best = Some(candidate);
        }
        if done {
            break;
        }
        h *= (c.max(1) as f64 / n as f64).sqrt();
    }
    best.unwrap_or_else(|| layout(h))
}

/// The rows of a hexagonal lattice of spacing `h` covering the box `[lo, hi]`: row `j` is at
/// height `y_j` (rows `h√3/2` apart) and holds the abscissae `x0_j + i h` (odd rows shifted by
/// `h/2`). The lattice is anchored at the box centre so that it does not depend on where the box
/// lies. Returns `(y_j, x-values)` per row.
pub fn hex_rows(lo: [f64; 2], hi: [f64; 2], h: f64) -> Vec<(f64, Vec<f64>)> {
    let dy = h * 3f64.sqrt() / 2.0;
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let j_lo = ((lo[1] - c[1]) / dy).floor() as i64 - 1;
    let j_hi = ((hi[1] - c[1]) / dy).ceil() as i64 + 1;
    let i_lo = ((lo[0] - c[0]) / h).floor() as i64 - 1;
    let i_hi = ((hi[0] - c[0]) / h).ceil() as i64 + 1;
    (j_lo..=j_hi)
        .map(|j| {
            let shift = if j.rem_euclid(2) == 1 { 0.5 * h } else { 0.0 };
            let xs = (i_lo..=i_hi)
                .map(|i| c[0] + i as f64 * h + shift)
                .filter(|x| *x >= lo[0] && *x <= hi[0])
                .collect();
            (c[1] + j as f64 * dy, xs)
        })
        .filter(|(y, _)| *y >= lo[1] && *y <= hi[1])
        .collect()
}

/// A point on a closed polyline: on its edge `edge` (from vertex `edge` to `edge + 1`, wrapping)
/// at parameter `t ∈ [0, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnPolyline {
    /// The edge (index of its first vertex).
    pub edge: usize,
    /// The parameter along the edge.
    pub t: f64,
    /// The point itself.
    pub point: [f64; 2],
}

/// `max(3, round(L / h))` points along the closed polyline `poly`, the first at `poly[0]`,
/// equally spaced with respect to the edge lengths `lengths` (edge `e` from `poly[e]` to
/// `poly[e + 1]`; L their sum), which may measure the edges otherwise than `poly` draws them.
pub fn resample_closed(poly: &[[f64; 2]], lengths: &[f64], h: f64) -> Vec<OnPolyline> {
    let m = poly.len();
    let total: f64 = lengths.iter().sum();
    let n = ((total / h).round() as usize).max(3);
    let mut out = Vec::with_capacity(n);
    let (mut e, mut start) = (0usize, 0.0f64);
    for k in 0..n {
        let s = total * k as f64 / n as f64;
        while e + 1 < m && start + lengths[e] <= s {
            start += lengths[e];
            e += 1;
        }
        let t = if lengths[e] > 0.0 {
            ((s - start) / lengths[e]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (poly[e], poly[(e + 1) % m]);
        out.push(OnPolyline {
            edge: e,
            t,
            point: [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
        });
    }
    out
}

/// Euclidean distance in the plane.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_lattice_has_the_density_it_claims() {
        let h = 0.05;
        let rows = hex_rows([0.0, 0.0], [2.0, 1.0], h);
        let n: usize = rows.iter().map(|r| r.1.len()).sum();
        let expected = 2.0 * hex_density(h);
        assert!(
            (n as f64 - expected).abs() / expected < 0.05,
            "{n} vs {expected}"
        );
        // Nearest neighbours are h apart, between and within rows.
        let (y0, x0) = (&rows[3].0, &rows[3].1);
        let (y1, x1) = (&rows[4].0, &rows[4].1);
        assert!((x0[1] - x0[0] - h).abs() < 1e-12);
        let d = x1
            .iter()
            .map(|x| dist([*x, *y1], [x0[5], *y0]))
            .fold(f64::INFINITY, f64::min);
        assert!((d - h).abs() < 1e-12);
        assert!((hex_spacing(2.0, n) - h).abs() / h < 0.03);
    }

    #[test]
    fn resampling_a_square_spaces_points_evenly() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let sides = [1.0; 4];
        let pts = resample_closed(&sq, &sides, 0.1);
        assert_eq!(pts.len(), 40);
        for (k, p) in pts.iter().enumerate() {
            let q = pts[(k + 1) % pts.len()].point;
            assert!((dist(p.point, q) - 0.1).abs() < 1e-9);
            let (a, b) = (sq[p.edge], sq[(p.edge + 1) % 4]);
            let on = [a[0] + p.t * (b[0] - a[0]), a[1] + p.t * (b[1] - a[1])];
            assert!(dist(on, p.point) < 1e-15);
        }
        assert_eq!(resample_closed(&sq, &sides, 10.0).len(), 3);
        // Edges measured as 1, 3, 1, 3: a quarter of the points on each short side.
        let pts = resample_closed(&sq, &[1.0, 3.0, 1.0, 3.0], 0.5);
        assert_eq!(pts.len(), 16);
        assert_eq!(pts.iter().filter(|p| p.edge == 0).count(), 2);
        assert_eq!(pts.iter().filter(|p| p.edge == 1).count(), 6);
    }
}
