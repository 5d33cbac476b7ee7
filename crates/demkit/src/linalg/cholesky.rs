//! A sparse Cholesky factorization whose symbolic analysis (ordering, elimination tree) is done
//! once per sparsity pattern; each iteration only refactors numerically.

use super::StiffnessPattern;
use crate::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

/// The symbolic Cholesky analysis of a [`StiffnessPattern`], reusable for any values.
#[derive(Debug, Clone)]
pub struct CachedCholesky {
    symbolic: SymbolicLlt<usize>,
    n: usize,
}

/// A numeric Cholesky factor `M = L Lᵀ` ready to solve.
#[derive(Debug)]
pub struct CholeskyFactor {
    llt: Llt<usize, f64>,
    n: usize,
}

impl CachedCholesky {
    /// Analyses the pattern (fill-reducing ordering and symbolic factorization).
    pub fn new(pattern: &StiffnessPattern) -> Result<Self> {
        let n = pattern.n_unknowns();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, pattern.col_ptr(), None, pattern.row_idx());
        let symbolic = SymbolicLlt::try_new(sym, Side::Lower)
            .map_err(|e| Error::Numerical(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        Ok(Self { symbolic, n })
    }

    /// Numeric factorization of the matrix with `values` on `pattern` (the same pattern as in
    /// [`new`](Self::new)). Fails if the matrix is not positive definite.
    pub fn factor(&self, pattern: &StiffnessPattern, values: &[f64]) -> Result<CholeskyFactor> {
        let sym = SymbolicSparseColMatRef::new_checked(self.n, self.n, pattern.col_ptr(), None, pattern.row_idx());
        let mat = SparseColMatRef::new(sym, values);
        let llt = Llt::try_new_with_symbolic(self.symbolic.clone(), mat, Side::Lower)
            .map_err(|e| Error::Numerical(format!("matrix is not positive definite ({e:?})")))?;
        Ok(CholeskyFactor { llt, n: self.n })
    }
}

impl CholeskyFactor {
    /// Solves `M x = b` in place for one right-hand side.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        debug_assert_eq!(b.len(), self.n);
        let n = b.len();
        let m = MatMut::from_column_major_slice_mut(b, n, 1);
        self.llt.solve_in_place(m);
    }

    /// Solves `M X = B` in place for `k` right-hand sides stored column-major in `b`.
    pub fn solve_many_in_place(&self, b: &mut [f64], k: usize) {
        debug_assert_eq!(b.len(), self.n * k);
        let m = MatMut::from_column_major_slice_mut(b, self.n, k);
        self.llt.solve_in_place(m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_refactors_with_new_values() {
        // A 3x3 grid of squares; fix the boundary; graph Laplacian + identity.
        let mut faces = Vec::new();
        let n = 4u32;
        for j in 0..3 {
            for i in 0..3 {
                let a = j * n + i;
                faces.push([a, a + 1, a + n + 1]);
                faces.push([a, a + n + 1, a + n]);
            }
        }
        let fixed: Vec<bool> = (0..16).map(|v| v % 4 == 0 || v % 4 == 3 || v < 4 || v >= 12).collect();
        let p = StiffnessPattern::new(16, &faces, Some(&fixed));
        assert_eq!(p.n_unknowns(), 4);
        let chol = CachedCholesky::new(&p).unwrap();
        for scale in [1.0, 3.0] {
            let w = vec![[scale; 3]; faces.len()];
            let mut v = vec![0.0; p.nnz()];
            p.assemble(&w, &[1.0; 16], &mut v);
            let f = chol.factor(&p, &v).unwrap();
            let b = vec![1.0, 2.0, 3.0, 4.0];
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            let r = p.mul(&v, &x);
            for i in 0..4 {
                assert!((r[i] - b[i]).abs() < 1e-12, "residual {}", r[i] - b[i]);
            }
        }
    }

    #[test]
    fn indefinite_matrix_is_an_error_not_a_panic() {
        let faces = vec![[0u32, 1, 2]];
        let p = StiffnessPattern::new(3, &faces, None);
        let chol = CachedCholesky::new(&p).unwrap();
        let w = vec![[1.0; 3]];
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[-10.0; 3], &mut v);
        assert!(chol.factor(&p, &v).is_err());
    }
}
