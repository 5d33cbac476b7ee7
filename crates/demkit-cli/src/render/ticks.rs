//! Ticks of the pictures' axes and colour bars: where they go (1–2–5 steps on a log axis, a
//! round top for a count axis) and how their values are written.

/// The 1–2–5 values strictly between `a` and `b` (0 < a < b; only the powers of ten when they
/// span over two decades), ascending: the ticks of a log axis.
pub fn log_ticks(a: f64, b: f64) -> Vec<f64> {
    let steps: &[f64] = if b / a > 100.0 {
        &[1.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    let mut t = Vec::new();
    for k in -6..=6 {
        for m in steps {
            let v = m * 10f64.powi(k);
            if v > a * 1.001 && v < b / 1.001 {
                t.push(v);
            }
        }
    }
    t
}

/// A short label for a tick value: at most two significant digits below 10.
pub fn label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let k = v.abs().log10().round();
    if !(1e-3..1e4).contains(&v) && (v / 10f64.powf(k) - 1.0).abs() < 1e-9 {
        return format!("1e{k}");
    }
    let decimals = if v >= 10.0 {
        0
    } else if v >= 1.0 {
        2
    } else {
        ((-v.abs().log10()).ceil() as usize).min(12) + 1
    };
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The top of a count axis holding `max` (a fraction): the next of 1, 2, 2.5, 5 × 10^k, and
/// the step between its ticks.
pub fn nice_top(max: f64) -> (f64, f64) {
    if max.is_nan() || max <= 0.0 {
        return (1.0, 0.2);
    }
    let p = 10f64.powf(max.log10().floor());
    for (m, step) in [(1.0, 0.2), (2.0, 0.5), (2.5, 0.5), (5.0, 1.0), (10.0, 2.0)] {
        if m * p >= max * (1.0 - 1e-12) {
            return (m * p, step * p);
        }
    }
    (10.0 * p, 2.0 * p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels() {
        let l: Vec<String> = [
            0.8,
            1.0,
            1.25,
            1.0 / 1.1,
            1.0 / 3.0,
            0.001,
            20.0,
            0.5,
            1e4,
            1e-4,
            0.0,
        ]
        .iter()
        .map(|&v| label(v))
        .collect();
        assert_eq!(
            l,
            [
                "0.8", "1", "1.25", "0.91", "0.33", "0.001", "20", "0.5", "1e4", "1e-4", "0"
            ]
        );
    }

    #[test]
    fn nice_tops() {
        assert_eq!(nice_top(0.07), (0.1, 0.02));
        assert_eq!(nice_top(0.2), (0.2, 0.05));
        assert_eq!(nice_top(0.21), (0.25, 0.05));
        assert_eq!(nice_top(0.3), (0.5, 0.1));
        assert_eq!(nice_top(1.0), (1.0, 0.2));
        assert_eq!(nice_top(0.0), (1.0, 0.2));
    }
}
