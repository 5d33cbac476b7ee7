//! Small dense systems (a hole's rigid-motion fit, the landmarks' interpolation): LU with
//! partial pivoting.

use faer::Mat;
use faer::linalg::solvers::Solve;

/// Solves `A X = B` for the `n × n` matrix `a` (row-major) and `k` right-hand sides `b`
/// (row-major, `n × k`); `None` when `A` is singular (the solution is not finite).
pub fn solve_dense(n: usize, a: &[f64], b: &[f64], k: usize) -> Option<Vec<f64>> {
    debug_assert!(a.len() == n * n && b.len() == n * k);
    let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let rhs = Mat::from_fn(n, k, |i, j| b[i * k + j]);
    let x = m.partial_piv_lu().solve(&rhs);
    let out: Vec<f64> = (0..n * k).map(|t| x[(t / k, t % k)]).collect();
    out.iter().all(|v| v.is_finite()).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_with_pivoting_and_reports_singular_systems() {
        // [[0, 2], [1, 1]] x = [[2, 4], [2, 3]] → x = [[1, 1], [1, 2]] (needs a row swap).
        let x = solve_dense(2, &[0.0, 2.0, 1.0, 1.0], &[2.0, 4.0, 2.0, 3.0], 2).unwrap();
        for (a, b) in x.iter().zip([1.0, 1.0, 1.0, 2.0]) {
            assert!((a - b).abs() < 1e-14, "{x:?}");
        }
        assert!(solve_dense(2, &[1.0, 2.0, 2.0, 4.0], &[1.0, 1.0], 1).is_none());
    }
}
