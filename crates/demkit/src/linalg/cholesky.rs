//! A sparse Cholesky factorization whose symbolic analysis (ordering, elimination tree,
//! supernodes) is done once per sparsity pattern; each iteration only refactors numerically,
//! reusing its workspace.
//!
//! The factorization runs single-threaded: on the mesh sizes demkit meets (10⁴–10⁶ unknowns,
//! planar graphs with small supernodes) faer's multi-threaded kernels spent most of their time
//! synchronizing (measured with `perf` on a 2-core machine); assembly is parallel instead.

use super::StiffnessPattern;
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::cell::RefCell;

/// The symbolic Cholesky analysis of a [`StiffnessPattern`], reusable for any values.
pub struct CachedCholesky {
    symbolic: SymbolicCholesky<usize>,
    n: usize,
    workspace: RefCell<MemBuffer>,
    /// The factor's values, lent to the live [`CholeskyFactor`] and returned when it drops, so
    /// refactorizations do not allocate.
    factor_values: RefCell<Vec<f64>>,
}

impl std::fmt::Debug for CachedCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CachedCholesky")
            .field("n", &self.n)
            .field("factor_len", &self.symbolic.len_val())
            .finish()
    }
}

/// A numeric Cholesky factor `M = L Lᵀ` ready to solve.
#[derive(Debug)]
pub struct CholeskyFactor<'a> {
    symbolic: &'a SymbolicCholesky<usize>,
    values: Vec<f64>,
    n: usize,
    home: &'a RefCell<Vec<f64>>,
}

impl Drop for CholeskyFactor<'_> {
    fn drop(&mut self) {
        self.home.replace(std::mem::take(&mut self.values));
    }
}

/// The symbolic analysis' parameters: always the supernodal factorization. faer's default
/// heuristic picks the simplicial one for the planar mesh matrices demkit factors, which
/// measured 1.1–1.6× slower here (human_face: DEM 4.1 s → 3.7 s; DEQ with 10 Newton
/// iterations on a face with two holes 6.9 s → 4.4 s).
pub(crate) fn supernodal_params() -> faer::sparse::linalg::cholesky::CholeskySymbolicParams<'static>
{
    faer::sparse::linalg::cholesky::CholeskySymbolicParams {
        supernodal_flop_ratio_threshold:
            faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    }
}

fn new_workspace(symbolic: &SymbolicCholesky<usize>) -> MemBuffer {
    let req = StackReq::any_of(&[
        symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(2, Par::Seq),
    ]);
    MemBuffer::new(req)
}

impl CachedCholesky {
    /// Analyses the pattern (fill-reducing ordering and symbolic factorization).
    pub fn new(pattern: &StiffnessPattern) -> Result<Self> {
        let n = pattern.n_unknowns();
        let sym =
            SymbolicSparseColMatRef::new_checked(n, n, pattern.col_ptr(), None, pattern.row_idx());
        let symbolic =
            factorize_symbolic_cholesky(sym, Side::Lower, Default::default(), supernodal_params())
                .map_err(|e| {
                    Error::Numerical(format!("symbolic Cholesky analysis failed: {e:?}"))
                })?;
        let workspace = RefCell::new(new_workspace(&symbolic));
        Ok(Self {
            symbolic,
            n,
            workspace,
            factor_values: RefCell::new(Vec::new()),
        })
    }

    /// Numeric factorization of the matrix with `values` on `pattern` (the same pattern as in
    /// [`new`](Self::new)). Fails if the matrix is not positive definite.
    pub fn factor(&self, pattern: &StiffnessPattern, values: &[f64]) -> Result<CholeskyFactor<'_>> {
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            pattern.col_ptr(),
            None,
            pattern.row_idx(),
        );
        let mat = SparseColMatRef::new(sym, values);
        let mut l = self.factor_values.take();
        l.resize(self.symbolic.len_val(), 0.0);
        let mut ws = self.workspace.borrow_mut();
        self.symbolic
            .factorize_numeric_llt(
                &mut l,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut ws),
                Default::default(),
            )
            .map_err(|e| Error::Numerical(format!("matrix is not positive definite ({e:?})")))?;
        Ok(CholeskyFactor {
            symbolic: &self.symbolic,
            values: l,
            n: self.n,
            home: &self.factor_values,
        })
    }
}

impl CholeskyFactor<'_> {
    /// Solves `M x = b` in place for one right-hand side.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.solve_many_in_place(b, 1);
    }

    /// Solves `M X = B` in place for `k` right-hand sides stored column-major in `b`.
    pub fn solve_many_in_place(&self, b: &mut [f64], k: usize) {
        debug_assert_eq!(b.len(), self.n * k);
        let mut buf = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
        let m = MatMut::from_column_major_slice_mut(b, self.n, k);
        LltRef::new(self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut buf),
        );
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
        let fixed: Vec<bool> = (0..16)
            .map(|v| v % 4 == 0 || v % 4 == 3 || !(4..12).contains(&v))
            .collect();
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
