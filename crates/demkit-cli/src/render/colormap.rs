//! Colours for values: the perceptually uniform viridis map (dark purple → blue → green →
//! yellow) and a diverging blue → white → red map (ColorBrewer's RdBu, reversed) for ratios
//! centred on 1, each by linear interpolation between samples.

use super::raster::Rgb;

/// Viridis at t = 0, 1/8, …, 1.
const STOPS: [Rgb; 9] = [
    [0x44, 0x01, 0x54],
    [0x47, 0x2d, 0x7b],
    [0x3b, 0x52, 0x8b],
    [0x2c, 0x72, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x28, 0xae, 0x80],
    [0x5e, 0xc9, 0x62],
    [0xad, 0xdc, 0x30],
    [0xfd, 0xe7, 0x25],
];

/// RdBu at t = 0, 0.1, …, 1, reversed: blue below the middle, near-white at ½, red above.
const DIVERGING: [Rgb; 11] = [
    [0x05, 0x30, 0x61],
    [0x21, 0x66, 0xac],
    [0x43, 0x93, 0xc3],
    [0x92, 0xc5, 0xde],
    [0xd1, 0xe5, 0xf0],
    [0xf7, 0xf7, 0xf7],
    [0xfd, 0xdb, 0xc7],
    [0xf4, 0xa5, 0x82],
    [0xd6, 0x60, 0x4d],
    [0xb2, 0x18, 0x2b],
    [0x67, 0x00, 0x1f],
];

/// The viridis colour of `t` in [0, 1] (clamped); NaN is mid grey.
pub fn viridis(t: f64) -> Rgb {
    interpolate(&STOPS, t)
}

/// The diverging colour of `t` in [0, 1] (clamped): ½ is near-white; NaN is mid grey.
pub fn diverging(t: f64) -> Rgb {
    interpolate(&DIVERGING, t)
}

/// Linear interpolation between equally spaced `stops`.
fn interpolate(stops: &[Rgb], t: f64) -> Rgb {
    if t.is_nan() {
        return [128, 128, 128];
    }
    let s = t.clamp(0.0, 1.0) * (stops.len() - 1) as f64;
    let i = (s.floor() as usize).min(stops.len() - 2);
    let f = s - i as f64;
    let (a, b) = (stops[i], stops[i + 1]);
    std::array::from_fn(|k| {
        (f64::from(a[k]) + f * (f64::from(b[k]) - f64::from(a[k]))).round() as u8
    })
}

/// The 0.5 % and 99.5 % quantiles of the finite values (the ends when those coincide);
/// `None` without finite values.
pub fn quantile_range(values: &[f64]) -> Option<(f64, f64)> {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    if sorted.is_empty() {
        return None;
    }
    let (lo, hi) = (
        demkit::metrics::quantile(&sorted, 0.005),
        demkit::metrics::quantile(&sorted, 0.995),
    );
    Some(if hi > lo {
        (lo, hi)
    } else {
        (sorted[0], sorted[sorted.len() - 1])
    })
}

/// Where each value falls in [0, 1] between the 0.5 % and 99.5 % quantiles of the finite
/// values (so a few outliers do not wash out the rest); all values equal → ½.
pub fn normalize(values: &[f64]) -> Vec<f64> {
    let Some((lo, hi)) = quantile_range(values) else {
        return vec![0.5; values.len()];
    };
    values
        .iter()
        .map(|&v| {
            if hi > lo {
                ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.5
            }
        })
        .collect()
}

/// `c` scaled by `k` (≥ 0) per channel, saturating.
pub fn shade(c: Rgb, k: f64) -> Rgb {
    c.map(|v| (f64::from(v) * k).round().clamp(0.0, 255.0) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_middle_and_clamping() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(0.5), [33, 145, 140]);
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), [128, 128, 128]);
        // Halfway between two stops.
        assert_eq!(viridis(1.0 / 16.0), [70, 23, 104]);
    }

    #[test]
    fn the_diverging_map_is_light_in_the_middle_and_dark_at_the_ends() {
        assert_eq!(diverging(0.5), [247, 247, 247]);
        assert_eq!(diverging(0.0), [5, 48, 97]);
        assert_eq!(diverging(1.0), [103, 0, 31]);
        let (low, high) = (diverging(0.3), diverging(0.7));
        assert!(low[2] > low[0] && high[0] > high[2], "{low:?} {high:?}");
        assert_eq!(diverging(f64::NAN), [128, 128, 128]);
    }

    #[test]
    fn lightness_grows_along_the_map() {
        let luma = |c: Rgb| 0.3 * f64::from(c[0]) + 0.59 * f64::from(c[1]) + 0.11 * f64::from(c[2]);
        let l: Vec<f64> = (0..=100).map(|i| luma(viridis(i as f64 / 100.0))).collect();
        assert!(l.windows(2).all(|w| w[1] >= w[0] - 0.5), "{l:?}");
    }

    #[test]
    fn normalize_spans_the_quantiles() {
        let v: Vec<f64> = (0..=1000).map(f64::from).collect();
        let t = normalize(&v);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[1000], 1.0);
        assert!((t[500] - 0.5).abs() < 1e-12);
        assert_eq!(normalize(&[3.0, 3.0]), vec![0.5, 0.5]);
        // Two values only: the quantiles are near the ends, which are kept apart.
        let t = normalize(&[1.0, 2.0]);
        assert!(t[0] < 0.01 && t[1] > 0.99, "{t:?}");
    }

    #[test]
    fn shade_scales_and_saturates() {
        assert_eq!(shade([100, 200, 50], 0.5), [50, 100, 25]);
        assert_eq!(shade([100, 200, 50], 2.0), [200, 255, 100]);
    }
}
