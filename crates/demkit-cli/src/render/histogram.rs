//! The density histograms of the papers' figures (DEM paper Figs. 6–11, SDEM paper Fig. 6,
//! DEQ paper Fig. 6): the density P(T)/A(T) of every face over its mean ΣP/ΣA, on the initial
//! and on the final map, counted in the same bins.
//!
//! The bins are equal on a log scale, ratio 1 in the middle of one; the axis runs from 1/R₁
//! to R₂, each chosen from a short list of round ratios so that both distributions fit (up
//! to their 0.5 % tails, which go into the end bins). A perfectly density-equalizing map puts
//! every face in the bin of ratio 1.

/// Ratio bounds of the axis, smallest first.
const RATIOS: [f64; 12] = [
    1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 1e3, 1e4,
];

/// About this many bins per histogram.
pub const BINS: usize = 61;

/// Each face's density P/A divided by the mean density ΣP/ΣA.
pub fn normalized_densities(population: &[f64], areas: &[f64]) -> Vec<f64> {
    let mean = population.iter().sum::<f64>() / areas.iter().sum::<f64>();
    population
        .iter()
        .zip(areas)
        .map(|(p, a)| p / a / mean)
        .collect()
}

/// The bins of the density axis: bin k (from −`below` to `above`) holds the ratios whose log
/// is within `width`/2 of k·`width`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// Bin width in log(ratio).
    pub width: f64,
    /// Bins below ratio 1's.
    pub below: usize,
    /// Bins above ratio 1's.
    pub above: usize,
    /// The listed ratios the axis must reach: 1/`low` and `high`.
    pub low: f64,
    /// See `low`.
    pub high: f64,
}

impl Axis {
    /// The axis holding every set's 0.5 % and 99.5 % quantiles, in about `bins` bins.
    pub fn fit(sets: &[&[f64]], bins: usize) -> Axis {
        let (mut need_low, mut need_high): (f64, f64) = (1.0, 1.0);
        for set in sets {
            let mut logs: Vec<f64> = set
                .iter()
                .filter(|v| v.is_finite() && **v > 0.0)
                .map(|v| v.ln())
                .collect();
            if logs.is_empty() {
                continue;
            }
            logs.sort_by(f64::total_cmp);
            need_low = need_low.max((-demkit::metrics::quantile(&logs, 0.005)).exp());
            need_high = need_high.max(demkit::metrics::quantile(&logs, 0.995).exp());
        }
        let pick = |need: f64| {
            RATIOS
                .iter()
                .copied()
                .find(|&r| r >= need * (1.0 - 1e-12))
                .unwrap_or(RATIOS[RATIOS.len() - 1])
        };
        let (low, high) = (pick(need_low), pick(need_high));
        let width = (low.ln() + high.ln()) / (bins.max(3) - 1) as f64;
        Axis {
            width,
            below: (low.ln() / width).round() as usize,
            above: (high.ln() / width).round() as usize,
            low,
            high,
        }
    }

    /// The number of bins.
    pub fn bins(&self) -> usize {
        self.below + self.above + 1
    }

    /// The ends of the axis in log(ratio).
    pub fn ends(&self) -> (f64, f64) {
        (
            -(self.below as f64 + 0.5) * self.width,
            (self.above as f64 + 0.5) * self.width,
        )
    }

    /// The bin (0-based from the lowest) of `value`; values beyond the ends (0 and +∞
    /// included) go into the end bins; NaN has none.
    pub fn bin_of(&self, value: f64) -> Option<usize> {
        if value.is_nan() {
            return None;
        }
        let k = (value.ln() / self.width).round();
        let k = k.clamp(-(self.below as f64), self.above as f64);
        Some((k + self.below as f64) as usize)
    }

    /// The number of values in each bin (see [`Axis::bin_of`]).
    pub fn counts(&self, values: &[f64]) -> Vec<usize> {
        let mut c = vec![0; self.bins()];
        for &v in values {
            if let Some(b) = self.bin_of(v) {
                c[b] += 1;
            }
        }
        c
    }

    /// The ticks: 1/`low`, `high`, and the 1–2–5 ratios between them (only the powers of ten
    /// when the axis spans more than two decades), ascending.
    pub fn ticks(&self) -> Vec<f64> {
        let mut t = vec![1.0 / self.low, self.high];
        t.extend(super::ticks::log_ticks(1.0 / self.low, self.high));
        t.sort_by(f64::total_cmp);
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_are_divided_by_their_mean() {
        // P = (1, 3), A = (1, 1): mean density 2.
        assert_eq!(
            normalized_densities(&[1.0, 3.0], &[1.0, 1.0]),
            vec![0.5, 1.5]
        );
        // Population equal to area: every face at 1.
        let d = normalized_densities(&[0.2, 0.7], &[0.2, 0.7]);
        assert!(d.iter().all(|v| (v - 1.0).abs() < 1e-15));
    }

    #[test]
    fn the_bins_count_every_value() {
        let axis = Axis::fit(&[&[0.5, 2.0]], BINS);
        assert_eq!((axis.low, axis.high), (2.0, 2.0));
        assert_eq!((axis.below, axis.above, axis.bins()), (30, 30, 61));
        let values = [
            1.0,
            0.5,
            2.0,
            1e-9,
            1e9,
            0.0,
            f64::INFINITY,
            1.01,
            0.99,
            f64::NAN,
        ];
        let c = axis.counts(&values);
        assert_eq!(c.len(), 61);
        assert_eq!(c.iter().sum::<usize>(), values.len() - 1, "all but NaN");
        // 1 is the middle bin; 1/2 and 2 are the middles of the end bins.
        assert_eq!(axis.bin_of(1.0), Some(30));
        assert_eq!(axis.bin_of(0.5), Some(0));
        assert_eq!(axis.bin_of(2.0), Some(60));
        assert_eq!(c[0], 3, "0.5, 1e-9, 0");
        assert_eq!(c[60], 3, "2, 1e9, inf");
        assert_eq!(
            c[30], 3,
            "1, 1.01, 0.99 (the middle bin is 2^(2/60) ≈ 1.023 wide)"
        );
        let (lo, hi) = axis.ends();
        assert!((lo + 2f64.ln() * 61.0 / 60.0).abs() < 1e-12 && (hi + lo).abs() < 1e-12);
    }

    #[test]
    fn the_axis_holds_both_sets() {
        let narrow = vec![1.0; 100];
        let wide: Vec<f64> = (0..100).map(|i| 0.3 + 0.03 * f64::from(i)).collect();
        let a = Axis::fit(&[&narrow], BINS);
        assert_eq!((a.low, a.high), (1.1, 1.1));
        // 0.3 … 3.27: the quantiles need 1/0.3 ≈ 3.3 below (5) and 3.26 above (5).
        let a = Axis::fit(&[&narrow, &wide], BINS);
        assert_eq!((a.low, a.high), (5.0, 5.0));
        // Lopsided: 1 … 1000 needs nothing below.
        let a = Axis::fit(&[&[1.0, 1000.0]], BINS);
        assert_eq!((a.low, a.high), (1.1, 1e3));
        assert_eq!(a.bins(), 61);
        assert_eq!(a.bin_of(1.0), Some(a.below));
        assert_eq!(Axis::fit(&[&[1e-9, 1e9]], BINS).high, 1e4);
    }

    #[test]
    fn axis_ticks() {
        let axis = |low, high| Axis {
            width: 0.1,
            below: 1,
            above: 1,
            low,
            high,
        };
        assert_eq!(axis(2.0, 2.0).ticks(), vec![0.5, 1.0, 2.0]);
        assert_eq!(
            axis(10.0, 10.0).ticks(),
            vec![0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0]
        );
        assert_eq!(
            axis(1.1, 1000.0).ticks(),
            vec![1.0 / 1.1, 1.0, 10.0, 100.0, 1e3]
        );
        assert_eq!(axis(1.25, 1.25).ticks(), vec![0.8, 1.0, 1.25]);
    }
}
