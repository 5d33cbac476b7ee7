//! Derivative-free minimization of functions of one or two real variables: the few parameters
//! that maps choose by a search (a translation of the flat torus, the dilation of an
//! ellipsoidal conformal map, a disk automorphism, the radii of EDEQ's ellipsoid).

/// The golden ratio's conjugate (√5 − 1)/2: each golden-section step keeps this share of the
/// bracket.
const GOLDEN: f64 = 0.618_033_988_749_894_9;

/// The least of `f` over `[lo, hi]`: `samples` evenly spaced values (the ends included, at
/// least 2), then `refinements` golden-section steps in the bracket around the best sample.
/// Returns the point and its value; the best sample's when the refinement finds nothing lower
/// (so a function with several minima gets the sampled grid's best one refined). The bracket
/// reaches one sample spacing beyond the best sample on both sides, so the refinement may look
/// that far past an end of the range (for a periodic function, the next period).
pub(crate) fn sampled_golden_section(
    f: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    samples: usize,
    refinements: usize,
) -> (f64, f64) {
    let samples = samples.max(2);
    let step = (hi - lo) / (samples - 1) as f64;
    let mut best = (lo, f(lo));
    for i in 1..samples {
        let t = lo + step * i as f64;
        let v = f(t);
        if v < best.1 {
            best = (t, v);
        }
    }
    let (mut a, mut b) = (best.0 - step, best.0 + step);
    let mut x1 = b - GOLDEN * (b - a);
    let mut x2 = a + GOLDEN * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..refinements {
        if f1 < f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - GOLDEN * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + GOLDEN * (b - a);
            f2 = f(x2);
        }
    }
    let refined = if f1 < f2 { (x1, f1) } else { (x2, f2) };
    if refined.1 < best.1 { refined } else { best }
}

/// Nelder–Mead minimisation of `f` over the plane from `x0` with initial step `step`, at most
/// `iterations` steps, stopping when the simplex's values agree to 1e-10 (relative) or its
/// corners lie within `size_tol` of the best in each coordinate (0: no such stop).
pub(crate) fn nelder_mead(
    f: impl Fn([f64; 2]) -> f64,
    x0: [f64; 2],
    step: f64,
    iterations: usize,
    size_tol: f64,
) -> ([f64; 2], f64) {
    let mut s = [x0, [x0[0] + step, x0[1]], [x0[0], x0[1] + step]];
    let mut v = s.map(&f);
    for _ in 0..iterations {
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        s = idx.map(|i| s[i]);
        v = idx.map(|i| v[i]);
        if (v[2] - v[0]).abs() <= 1e-10 * v[0].abs().max(1e-300) {
            break;
        }
        let extent = (1..3)
            .flat_map(|i| (0..2).map(move |d| (i, d)))
            .map(|(i, d)| (s[i][d] - s[0][d]).abs())
            .fold(0.0, f64::max);
        if extent <= size_tol {
            break;
        }
        let c = [(s[0][0] + s[1][0]) / 2.0, (s[0][1] + s[1][1]) / 2.0];
        let at = |t: f64| [c[0] + t * (s[2][0] - c[0]), c[1] + t * (s[2][1] - c[1])];
        let r = at(-1.0);
        let fr = f(r);
        if fr < v[0] {
            let e = at(-2.0);
            let fe = f(e);
            if fe < fr {
                (s[2], v[2]) = (e, fe);
            } else {
                (s[2], v[2]) = (r, fr);
            }
        } else if fr < v[1] {
            (s[2], v[2]) = (r, fr);
        } else {
            let k = at(0.5);
            let fk = f(k);
            if fk < v[2] {
                (s[2], v[2]) = (k, fk);
            } else {
                for i in 1..3 {
                    s[i] = [(s[0][0] + s[i][0]) / 2.0, (s[0][1] + s[i][1]) / 2.0];
                    v[i] = f(s[i]);
                }
            }
        }
    }
    let i = (0..3).min_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap_or(0);
    (s[i], v[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nelder_mead_stops_once_its_simplex_is_small_enough() {
        // Without a size tolerance the search runs until the values agree to 1e-10; with one
        // of 1e-3 it stops sooner, within that distance of the minimum at (1, −2).
        let count = std::cell::Cell::new(0);
        let f = |x: [f64; 2]| {
            count.set(count.get() + 1);
            (x[0] - 1.0).powi(2) + 2.0 * (x[1] + 2.0).powi(2)
        };
        let (fine, _) = nelder_mead(f, [0.0, 0.0], 0.1, 500, 0.0);
        let all = count.replace(0);
        let (coarse, _) = nelder_mead(f, [0.0, 0.0], 0.1, 500, 1e-3);
        let few = count.get();
        assert!(
            few < all,
            "{few} evaluations with the size stop, {all} without"
        );
        assert!(
            (fine[0] - 1.0).abs() < 1e-4 && (fine[1] + 2.0).abs() < 1e-4,
            "{fine:?}"
        );
        assert!(
            (coarse[0] - 1.0).abs() < 5e-3 && (coarse[1] + 2.0).abs() < 5e-3,
            "{coarse:?}"
        );
    }

    #[test]
    fn nelder_mead_finds_the_minimum_of_a_quadratic_bowl() {
        let f = |x: [f64; 2]| (x[0] - 1.0).powi(2) + 3.0 * (x[1] + 0.5).powi(2) + x[0] * x[1];
        // Minimum where ∇f = 0: 2(x − 1) + y = 0, 6(y + 0.5) + x = 0.
        let (x, _) = nelder_mead(f, [0.0, 0.0], 0.1, 200, 0.0);
        let (x_exact, y_exact) = (15.0 / 11.0, -8.0 / 11.0);
        assert!(
            (x[0] - x_exact).abs() < 1e-4 && (x[1] - y_exact).abs() < 1e-4,
            "{x:?}"
        );
    }

    #[test]
    fn finds_the_minimum_of_a_parabola() {
        let (x, v) = sampled_golden_section(|t| (t - 0.3) * (t - 0.3) + 2.0, -1.0, 1.0, 9, 40);
        assert!((x - 0.3).abs() < 1e-7, "{x}");
        assert!((v - 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_samples_pick_the_deeper_of_two_minima() {
        // Minima near −0.8 (value −1) and 0.6 (value −2).
        let f =
            |t: f64| -(-(t + 0.8).powi(2) * 50.0).exp() - 2.0 * (-(t - 0.6).powi(2) * 50.0).exp();
        let (x, _) = sampled_golden_section(f, -1.0, 1.0, 41, 40);
        assert!((x - 0.6).abs() < 1e-3, "{x}");
    }

    #[test]
    fn the_refinement_looks_one_spacing_past_the_ends() {
        // Samples 0, 0.25, ..., 1: the best is 0 and the bracket [−0.25, 0.25].
        let (x, _) = sampled_golden_section(|t| t, 0.0, 1.0, 5, 30);
        assert!((x + 0.25).abs() < 1e-5, "{x}");
        let (x, _) = sampled_golden_section(|t| (t + 0.1).abs(), 0.0, 1.0, 5, 40);
        assert!((x + 0.1).abs() < 1e-6, "{x}");
    }
}
