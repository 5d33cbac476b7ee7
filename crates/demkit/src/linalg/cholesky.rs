//! The sparse Cholesky factorization `K = L Lᵀ` of a symmetric positive definite matrix given
//! by its lower triangle in compressed sparse columns (faer's supernodal factorization).
//!
//! The fill-reducing ordering (approximate minimum degree, or one given by the caller) and the
//! symbolic factorization (elimination tree, supernodes) are computed once per sparsity
//! pattern; each [`factor`](SparseCholesky::factor) only refactors numerically. The factor's
//! values and the scratch memory of factorization and solves live in the solver and are reused,
//! so neither a refactorization nor a solve allocates (the scratch grows once if a solve asks
//! for more right-hand sides than any before it).
//!
//! The factorization is supernodal and single-threaded (docs/deviations.md, sparse
//! factorization).

use super::{ElementPattern, StiffnessPattern};
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Sparse Cholesky `K = L Lᵀ` over one sparsity pattern: analysed once in
/// [`new`](Self::new) (or [`with_ordering`](Self::with_ordering),
/// [`for_pattern`](Self::for_pattern), [`for_stiffness`](Self::for_stiffness)), refactored
/// numerically by [`factor`](Self::factor) for every new set of values, and solved with the
/// last successful factorization.
pub struct SparseCholesky {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    workspace: MemBuffer,
    /// Right-hand sides a solve can take with the present `workspace`.
    solve_columns: usize,
    /// The values of `L`, overwritten by every factorization.
    factor: Vec<f64>,
    factored: bool,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("n", &self.n)
            .field("nnz", &self.row_idx.len())
            .field("factor_len", &self.symbolic.len_val())
            .finish()
    }
}

/// The symbolic analysis' parameters: always the supernodal factorization, where faer's
/// default heuristic would pick the simplicial one (docs/deviations.md, sparse factorization).
fn supernodal_params() -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    }
}

/// Scratch memory for a numeric factorization and for a solve with `columns` right-hand sides.
fn workspace(symbolic: &SymbolicCholesky<usize>, columns: usize) -> MemBuffer {
    MemBuffer::new(StackReq::any_of(&[
        symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(columns, Par::Seq),
    ]))
}

/// The inverse of the permutation `order` of `0..n`, or an error if it is not one.
fn inverse_permutation(order: &[usize], n: usize) -> Result<Vec<usize>> {
    let mut inv = vec![usize::MAX; n];
    if order.len() != n {
        return Err(Error::Argument(format!(
            "an ordering of {} entries for {n} unknowns",
            order.len()
        )));
    }
    for (k, &i) in order.iter().enumerate() {
        match inv.get_mut(i) {
            Some(slot) if *slot == usize::MAX => *slot = k,
            _ => {
                return Err(Error::Argument(format!(
                    "the ordering repeats or exceeds unknown {i}"
                )));
            }
        }
    }
    Ok(inv)
}

/// A fill-reducing elimination order (approximate minimum degree) of a symmetric sparsity
/// pattern given by its lower triangle in compressed sparse columns: `order[k]` is the index
/// eliminated k-th.
pub fn minimum_degree_order(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<Vec<usize>> {
    check_lower_csc(n, col_ptr, row_idx)?;
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, row_idx.len()));
    amd::order(
        &mut perm,
        &mut perm_inv,
        sym,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| Error::Numerical(format!("minimum degree ordering failed: {e:?}")))?;
    Ok(perm)
}

/// Checks that `(col_ptr, row_idx)` is a lower-triangular CSC structure of an `n × n` matrix
/// with sorted, distinct row indices.
fn check_lower_csc(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<()> {
    let bad = |msg: String| Err(Error::Argument(format!("sparse pattern: {msg}")));
    if col_ptr.len() != n + 1 || col_ptr[0] != 0 || col_ptr[n] != row_idx.len() {
        return bad(format!(
            "{} column pointers for {n} columns and {} entries",
            col_ptr.len(),
            row_idx.len()
        ));
    }
    for col in 0..n {
        let (a, b) = (col_ptr[col], col_ptr[col + 1]);
        if a > b {
            return bad(format!("column pointers decrease at column {col}"));
        }
        let rows = &row_idx[a..b];
        if rows.iter().any(|&r| r < col || r >= n) || rows.windows(2).any(|w| w[0] >= w[1]) {
            return bad(format!(
                "column {col} has rows that are unsorted, repeated, above the diagonal or \
                 out of range"
            ));
        }
    }
    Ok(())
}

impl SparseCholesky {
    /// Analyses the pattern: minimum degree ordering and symbolic factorization.
    ///
    /// Errors: a malformed structure ([`Error::Argument`]) or a failed analysis.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<Self> {
        Self::with_ordering(n, col_ptr, row_idx, None)
    }

    /// As [`new`](Self::new), eliminating the unknowns in the given `order` (`order[k]` is
    /// the unknown eliminated k-th) instead of computing a minimum degree ordering.
    ///
    /// Errors: as [`new`](Self::new), or `order` not a permutation of `0..n`.
    pub fn with_ordering(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        order: Option<&[usize]>,
    ) -> Result<Self> {
        check_lower_csc(n, col_ptr, row_idx)?;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
        let inverse = match order {
            Some(order) => Some(inverse_permutation(order, n)?),
            None => None,
        };
        let ordering = match (order, inverse.as_deref()) {
            (Some(fwd), Some(inv)) => SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
            _ => SymmetricOrdering::Amd,
        };
        let symbolic = factorize_symbolic_cholesky(sym, Side::Lower, ordering, supernodal_params())
            .map_err(|e| Error::Numerical(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        Ok(Self {
            n,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            workspace: workspace(&symbolic, 1),
            solve_columns: 1,
            factor: vec![0.0; symbolic.len_val()],
            symbolic,
            factored: false,
        })
    }

    /// The solver for an [`ElementPattern`]'s structure.
    pub fn for_pattern(pattern: &ElementPattern) -> Result<Self> {
        Self::new(pattern.n_unknowns(), pattern.col_ptr(), pattern.row_idx())
    }

    /// The solver for a [`StiffnessPattern`]'s structure.
    pub fn for_stiffness(pattern: &StiffnessPattern) -> Result<Self> {
        Self::for_stiffness_in(pattern, None)
    }

    /// The solver for a [`StiffnessPattern`]'s structure, eliminating its unknowns in the
    /// mesh's vertex `order` when one is given (computed once for the connectivity), else in
    /// a minimum degree order of its own.
    pub fn for_stiffness_in(
        pattern: &StiffnessPattern,
        order: Option<&super::VertexOrder>,
    ) -> Result<Self> {
        let order = order.map(|o| o.restricted_to(pattern));
        Self::with_ordering(
            pattern.n_unknowns(),
            pattern.col_ptr(),
            pattern.row_idx(),
            order.as_deref(),
        )
    }

    /// Numeric factorization of the matrix with `values` on the pattern given to
    /// [`new`](Self::new). Fails if the values are not finite or the matrix is not positive
    /// definite; solves then fail until a factorization succeeds.
    pub fn factor(&mut self, values: &[f64]) -> Result<()> {
        self.factored = false;
        if values.len() != self.row_idx.len() {
            return Err(Error::Argument(format!(
                "{} values for a pattern of {} entries",
                values.len(),
                self.row_idx.len()
            )));
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(Error::Numerical(
                "matrix to factor has non-finite entries".into(),
            ));
        }
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let mat = SparseColMatRef::new(sym, values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.workspace),
                Default::default(),
            )
            .map_err(|e| Error::Numerical(format!("matrix is not positive definite ({e:?})")))?;
        self.factored = true;
        Ok(())
    }

    /// Solves `K x = b` in place with the last successful [`factor`](Self::factor).
    ///
    /// Errors: no factorization yet or a wrong length.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        self.solve_many_in_place(b, 1)
    }

    /// As [`solve_in_place`](Self::solve_in_place), and an error if the solution has a
    /// non-finite entry (a near-singular matrix or a non-finite `b`).
    pub fn solve_finite_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        self.solve_in_place(b)?;
        if b.iter().any(|x| !x.is_finite()) {
            return Err(Error::Numerical(
                "Cholesky solve produced a non-finite solution".into(),
            ));
        }
        Ok(())
    }

    /// Solves `K X = B` in place for `k` right-hand sides stored column-major in `b`, with the
    /// last successful [`factor`](Self::factor).
    ///
    /// Errors: no factorization yet, or `b` not of length `n k`.
    pub fn solve_many_in_place(&mut self, b: &mut [f64], k: usize) -> Result<()> {
        if !self.factored {
            return Err(Error::Numerical(
                "solve before a successful factorization".into(),
            ));
        }
        if b.len() != self.n * k {
            return Err(Error::Argument(format!(
                "right-hand sides of length {} for {k} × {} unknowns",
                b.len(),
                self.n
            )));
        }
        if k > self.solve_columns {
            self.workspace = workspace(&self.symbolic, k);
            self.solve_columns = k;
        }
        let m = MatMut::from_column_major_slice_mut(b, self.n, k);
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut self.workspace),
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3x3 grid of squares with its boundary fixed: 4 unknowns.
    fn grid_pattern() -> (Vec<[u32; 3]>, StiffnessPattern) {
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
        (faces, p)
    }

    #[test]
    fn solves_and_refactors_with_new_values() {
        // Graph Laplacian + identity on the grid, one and two right-hand sides.
        let (faces, p) = grid_pattern();
        assert_eq!(p.n_unknowns(), 4);
        let mut chol = SparseCholesky::for_stiffness(&p).unwrap();
        for scale in [1.0, 3.0] {
            let w = vec![[scale; 3]; faces.len()];
            let mut v = vec![0.0; p.nnz()];
            p.assemble(&w, &[1.0; 16], &mut v);
            chol.factor(&v).unwrap();
            let b = vec![1.0, 2.0, 3.0, 4.0, -1.0, 0.5, 0.0, 2.0];
            let mut x = b.clone();
            chol.solve_in_place(&mut x[..4]).unwrap();
            chol.solve_many_in_place(&mut x[4..], 1).unwrap();
            let mut both = b.clone();
            chol.solve_many_in_place(&mut both, 2).unwrap();
            assert_eq!(both, x, "two columns at once solve as one at a time");
            for c in 0..2 {
                let r = p.mul(&v, &x[4 * c..4 * c + 4]);
                for i in 0..4 {
                    let e = r[i] - b[4 * c + i];
                    assert!(e.abs() < 1e-12, "residual {e}");
                }
            }
        }
    }

    #[test]
    fn orderings_change_the_factor_not_the_solution() {
        let (faces, p) = grid_pattern();
        let mut values = vec![0.0; p.nnz()];
        p.assemble(&vec![[1.0; 3]; faces.len()], &[0.5; 16], &mut values);
        let b = [1.0, 2.0, -1.0, 0.5];
        let amd = minimum_degree_order(4, p.col_ptr(), p.row_idx()).unwrap();
        let mut sorted = amd.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, [0, 1, 2, 3]);
        let mut solutions = Vec::new();
        for order in [None, Some(vec![3, 2, 1, 0]), Some(amd)] {
            let mut s =
                SparseCholesky::with_ordering(4, p.col_ptr(), p.row_idx(), order.as_deref())
                    .unwrap();
            s.factor(&values).unwrap();
            let mut x = b.to_vec();
            s.solve_finite_in_place(&mut x).unwrap();
            solutions.push(x);
        }
        for x in &solutions[1..] {
            for (a, b) in x.iter().zip(&solutions[0]) {
                assert!((a - b).abs() < 1e-13);
            }
        }
        let bad = SparseCholesky::with_ordering(4, p.col_ptr(), p.row_idx(), Some(&[0, 1, 1, 3]));
        assert!(bad.is_err());
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert!(SparseCholesky::new(2, &[0, 1], &[0]).is_err());
        assert!(SparseCholesky::new(2, &[0, 1, 2], &[1, 0]).is_err());
        // An untouched unknown leaves a zero diagonal: singular, reported by the factorization.
        let p = ElementPattern::new(2, [&[0u32][..]]).unwrap();
        let mut s = SparseCholesky::for_pattern(&p).unwrap();
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&[1.0], &mut v);
        assert!(s.factor(&v).is_err());
        let mut b = vec![1.0, 1.0];
        assert!(s.solve_in_place(&mut b).is_err());
        // Indefinite, then non-finite values, then a wrong length.
        let faces = vec![[0u32, 1, 2]];
        let p = StiffnessPattern::new(3, &faces, None);
        let mut s = SparseCholesky::for_stiffness(&p).unwrap();
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&[[1.0; 3]], &[-10.0; 3], &mut v);
        assert!(s.factor(&v).is_err());
        p.assemble(&[[1.0; 3]], &[1.0; 3], &mut v);
        s.factor(&v).unwrap();
        assert!(s.solve_in_place(&mut [1.0, 2.0]).is_err());
        let mut inf = [f64::INFINITY, 0.0, 0.0];
        s.solve_in_place(&mut inf).unwrap();
        assert!(s.solve_finite_in_place(&mut inf).is_err());
        v[0] = f64::NAN;
        assert!(s.factor(&v).is_err());
        assert!(s.solve_in_place(&mut [1.0; 3]).is_err());
    }
}
