//! Sparse LU for the non-symmetric systems (the locally authalic map).

use crate::{Error, Result};
use faer::MatMut;
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};

/// Solves `A X = B` for a sparse `n × n` matrix given as triplets (duplicates are summed) and
/// `k` right-hand sides stored column-major in `b` (overwritten with the solution).
pub fn solve_lu(n: usize, triplets: &[(usize, usize, f64)], b: &mut [f64], k: usize) -> Result<()> {
    let entries: Vec<Triplet<usize, usize, f64>> = triplets
        .iter()
        .map(|&(row, col, val)| Triplet { row, col, val })
        .collect();
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &entries)
        .map_err(|e| Error::Numerical(format!("sparse matrix assembly failed: {e:?}")))?;
    let lu = a
        .sp_lu()
        .map_err(|e| Error::Numerical(format!("sparse LU failed: {e:?}")))?;
    lu.solve_in_place(MatMut::from_column_major_slice_mut(b, n, k));
    if b.iter().any(|x| !x.is_finite()) {
        return Err(Error::Numerical(
            "sparse LU produced a non-finite solution (singular matrix)".into(),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_nonsymmetric_system() {
        // [[2,1],[0,3]] x = [5, 6] -> x = [1.5, 2]
        let t = [(0, 0, 2.0), (0, 1, 1.0), (1, 1, 1.5), (1, 1, 1.5)];
        let mut b = vec![5.0, 6.0];
        solve_lu(2, &t, &mut b, 1).unwrap();
        assert!((b[0] - 1.5).abs() < 1e-14 && (b[1] - 2.0).abs() < 1e-14);
    }
}
