//! A sparse symmetric positive definite solver for an arbitrary sparsity pattern, with the
//! symbolic analysis done once and a numeric refactorization per set of values, and an
//! element-by-element assembler whose gather is parallel.
//!
//! [`ElementPattern`] stores the matrix `K = Σ_e Sₑᵀ Kₑ Sₑ` assembled from small dense symmetric
//! element matrices `Kₑ` over lists of unknowns (`Sₑ` selects element `e`'s unknowns); the
//! lower triangle of `K` is kept in compressed sparse columns. [`SpdSolver`] factors `K = L Lᵀ`
//! (faer's supernodal Cholesky) after a fill-reducing ordering: approximate minimum degree, or
//! one given by the caller — e.g. expanded from [`minimum_degree_order`] of a smaller graph when
//! the unknowns come in blocks per mesh vertex, which is much cheaper to compute.

use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use rayon::prelude::*;

/// Index of the local entry `(a, b)`, `b ≤ a`, in an element's packed lower triangle.
#[inline]
pub fn packed_index(a: usize, b: usize) -> usize {
    a * (a + 1) / 2 + b
}

/// The sparsity pattern of a matrix assembled from dense element matrices, with, for each
/// stored entry, the element values that sum into it.
///
/// Element `e` has `m` distinct unknowns `u₀ … u_{m−1}` and stores its matrix `Kₑ` as the
/// packed lower triangle `Kₑ[a][b]`, `b ≤ a`, at [`packed_index`]`(a, b)` within its slice of
/// the element-value buffer (slices follow each other in element order).
#[derive(Debug, Clone)]
pub struct ElementPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    value_ptr: Vec<usize>,
    /// CSR over stored entries: the element-value slots summed into each entry.
    src_ptr: Vec<usize>,
    src: Vec<u32>,
}

impl ElementPattern {
    /// Builds the pattern of `n` unknowns from the unknown lists of the elements. Every unknown
    /// gets a diagonal entry, even one no element touches (its value is then 0 and the
    /// factorization fails, as the matrix is singular).
    ///
    /// Errors: an unknown `≥ n`, an unknown repeated within an element, or more element values
    /// than `u32` can index.
    pub fn new<'a>(n: usize, elements: impl IntoIterator<Item = &'a [u32]>) -> Result<Self> {
        // Local entries (column, row, slot) bucketed by column (counting sort), then sorted by
        // row within each column.
        let mut records: Vec<(u32, u32, u32)> = Vec::new();
        let mut value_ptr = vec![0usize];
        let mut slot = 0usize;
        for (e, unknowns) in elements.into_iter().enumerate() {
            for (a, &ua) in unknowns.iter().enumerate() {
                if ua as usize >= n {
                    return Err(Error::Argument(format!(
                        "element {e} refers to unknown {ua}, but there are only {n}"
                    )));
                }
                if unknowns[..a].contains(&ua) {
                    return Err(Error::Argument(format!(
                        "element {e} lists unknown {ua} twice"
                    )));
                }
                for &ub in &unknowns[..=a] {
                    let s = u32::try_from(slot).map_err(|_| {
                        Error::Argument("too many element values for u32 indices".into())
                    })?;
                    records.push((ua.min(ub), ua.max(ub), s));
                    slot += 1;
                }
            }
            value_ptr.push(slot);
        }
        let mut bucket_ptr = vec![0usize; n + 1];
        for &(col, _, _) in &records {
            bucket_ptr[col as usize + 1] += 1;
        }
        for c in 0..n {
            bucket_ptr[c + 1] += bucket_ptr[c];
        }
        let mut fill = bucket_ptr.clone();
        let mut bucket = vec![(0u32, 0u32); records.len()];
        for &(col, row, s) in &records {
            bucket[fill[col as usize]] = (row, s);
            fill[col as usize] += 1;
        }
        drop(records);
        // Sort each column's entries by row (in place, in parallel), then store one entry per
        // distinct row, the diagonal first (present even with no contribution).
        let mut columns: Vec<&mut [(u32, u32)]> = Vec::with_capacity(n);
        let mut rest = bucket.as_mut_slice();
        for c in 0..n {
            let (head, tail) =
                std::mem::take(&mut rest).split_at_mut(bucket_ptr[c + 1] - bucket_ptr[c]);
            columns.push(head);
            rest = tail;
        }
        columns.par_iter_mut().for_each(|col| col.sort_unstable());
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(bucket.len() / 2 + n);
        let mut src_ptr = Vec::with_capacity(bucket.len() / 2 + n);
        let mut src = Vec::with_capacity(slot);
        for (c, entries) in bucket_ptr
            .windows(2)
            .map(|w| &bucket[w[0]..w[1]])
            .enumerate()
        {
            col_ptr.push(row_idx.len());
            row_idx.push(c);
            src_ptr.push(src.len());
            for &(row, s) in entries {
                if row_idx.last() != Some(&(row as usize)) {
                    row_idx.push(row as usize);
                    src_ptr.push(src.len());
                }
                src.push(s);
            }
        }
        col_ptr.push(row_idx.len());
        src_ptr.push(src.len());
        Ok(Self {
            n,
            col_ptr,
            row_idx,
            value_ptr,
            src_ptr,
            src,
        })
    }

    /// Number of unknowns.
    pub fn n_unknowns(&self) -> usize {
        self.n
    }
    /// Number of stored entries (lower triangle with diagonal).
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
    /// Column pointers of the lower-triangular CSC structure.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }
    /// Row indices of the lower-triangular CSC structure (sorted, diagonal first).
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }
    /// Length of the element-value buffer (the packed triangles of all elements).
    pub fn n_element_values(&self) -> usize {
        self.value_ptr.last().copied().unwrap_or(0)
    }

    /// Splits the element-value buffer `buf` (length [`n_element_values`](Self::n_element_values))
    /// into one packed triangle per element, in element order.
    pub fn element_slices<'a>(&self, mut buf: &'a mut [f64]) -> Vec<&'a mut [f64]> {
        let mut out = Vec::with_capacity(self.value_ptr.len().saturating_sub(1));
        for w in self.value_ptr.windows(2) {
            let (head, tail) = std::mem::take(&mut buf).split_at_mut(w[1] - w[0]);
            out.push(head);
            buf = tail;
        }
        out
    }

    /// Sums the element values into the matrix values (length [`nnz`](Self::nnz)), in parallel.
    pub fn assemble(&self, element_values: &[f64], values: &mut [f64]) {
        values.par_iter_mut().enumerate().for_each(|(k, v)| {
            *v = self.src[self.src_ptr[k]..self.src_ptr[k + 1]]
                .iter()
                .map(|&s| element_values[s as usize])
                .sum();
        });
    }

    /// `y = K x` with the values from [`assemble`](Self::assemble) (both triangles).
    pub fn mul(&self, values: &[f64], x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for (col, range) in self.col_ptr.windows(2).enumerate() {
            let entries = self.row_idx[range[0]..range[1]]
                .iter()
                .zip(&values[range[0]..range[1]]);
            for (&row, &v) in entries {
                y[row] += v * x[col];
                if row != col {
                    y[col] += v * x[row];
                }
            }
        }
        y
    }
}

/// Sparse Cholesky `K = L Lᵀ` of a symmetric positive definite matrix given by its lower
/// triangle in compressed sparse columns. The ordering and symbolic factorization are computed
/// once in [`new`](Self::new); [`factor`](Self::factor) refactors numerically for new values.
/// Runs single-threaded (see [`super::CachedCholesky`] for why).
pub struct SpdSolver {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    workspace: MemBuffer,
    factor: Vec<f64>,
    factored: bool,
}

impl std::fmt::Debug for SpdSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpdSolver")
            .field("n", &self.n)
            .field("nnz", &self.row_idx.len())
            .field("factor_len", &self.symbolic.len_val())
            .finish()
    }
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

impl SpdSolver {
    /// Analyses the pattern: fill-reducing ordering and symbolic factorization.
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
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            ordering,
            super::cholesky::supernodal_params(),
        )
        .map_err(|e| Error::Numerical(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        Ok(Self {
            n,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            workspace: MemBuffer::new(req),
            factor: vec![0.0; symbolic.len_val()],
            symbolic,
            factored: false,
        })
    }

    /// The solver for an [`ElementPattern`]'s structure.
    pub fn for_pattern(pattern: &ElementPattern) -> Result<Self> {
        Self::new(pattern.n_unknowns(), pattern.col_ptr(), pattern.row_idx())
    }

    /// Number of unknowns.
    pub fn n_unknowns(&self) -> usize {
        self.n
    }

    /// Numeric factorization of the matrix with `values` on the pattern given to
    /// [`new`](Self::new). Fails if the values are not finite or the matrix is not positive
    /// definite.
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
    /// Errors: no factorization yet, a wrong length, or a non-finite solution.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        if !self.factored {
            return Err(Error::Numerical(
                "solve before a successful factorization".into(),
            ));
        }
        if b.len() != self.n {
            return Err(Error::Argument(format!(
                "right-hand side of length {} for {} unknowns",
                b.len(),
                self.n
            )));
        }
        let m = MatMut::from_column_major_slice_mut(b, self.n, 1);
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut self.workspace),
        );
        if b.iter().any(|x| !x.is_finite()) {
            return Err(Error::Numerical(
                "Cholesky solve produced a non-finite solution".into(),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Elements of a small system: a chain of pairs plus one element over three unknowns.
    fn elements() -> Vec<Vec<u32>> {
        vec![vec![0, 1], vec![1, 2], vec![2, 3], vec![3, 0, 2]]
    }

    /// Dense `K` summed from the element triangles (the reference).
    fn dense(n: usize, elements: &[Vec<u32>], ev: &[f64]) -> Vec<Vec<f64>> {
        let mut k = vec![vec![0.0; n]; n];
        let mut off = 0;
        for e in elements {
            for a in 0..e.len() {
                for b in 0..=a {
                    let v = ev[off + packed_index(a, b)];
                    let (i, j) = (e[a] as usize, e[b] as usize);
                    k[i][j] += v;
                    if i != j {
                        k[j][i] += v;
                    }
                }
            }
            off += e.len() * (e.len() + 1) / 2;
        }
        k
    }

    fn element_values(p: &ElementPattern, elements: &[Vec<u32>], scale: f64) -> Vec<f64> {
        let mut ev = vec![0.0; p.n_element_values()];
        for (e, s) in p.element_slices(&mut ev).into_iter().enumerate() {
            let m = elements[e].len();
            for a in 0..m {
                for b in 0..=a {
                    // Diagonally dominant: positive definite after summation.
                    s[packed_index(a, b)] = if a == b {
                        3.0 * scale
                    } else {
                        -0.5 + 0.1 * e as f64
                    };
                }
            }
        }
        ev
    }

    #[test]
    fn assembles_like_dense_and_solves_with_refactorization() {
        let els = elements();
        let p = ElementPattern::new(4, els.iter().map(|e| e.as_slice())).unwrap();
        assert_eq!(p.n_element_values(), 3 + 3 + 3 + 6);
        // Pairs (0,1) (1,2) (2,3) (0,3) (0,2) and 4 diagonals.
        assert_eq!(p.nnz(), 9);
        let mut solver = SpdSolver::for_pattern(&p).unwrap();
        for scale in [1.0, 2.5] {
            let ev = element_values(&p, &els, scale);
            let mut values = vec![0.0; p.nnz()];
            p.assemble(&ev, &mut values);
            let k = dense(4, &els, &ev);
            let x = [1.0, -2.0, 0.5, 3.0];
            let y = p.mul(&values, &x);
            for i in 0..4 {
                let want: f64 = (0..4).map(|j| k[i][j] * x[j]).sum();
                assert!((y[i] - want).abs() < 1e-13, "row {i}: {} vs {want}", y[i]);
            }
            solver.factor(&values).unwrap();
            let mut b = y.clone();
            solver.solve_in_place(&mut b).unwrap();
            for i in 0..4 {
                assert!((b[i] - x[i]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn orderings_change_the_factor_not_the_solution() {
        let els = elements();
        let p = ElementPattern::new(4, els.iter().map(|e| e.as_slice())).unwrap();
        let ev = element_values(&p, &els, 1.0);
        let mut values = vec![0.0; p.nnz()];
        p.assemble(&ev, &mut values);
        let b = [1.0, 2.0, -1.0, 0.5];
        let amd = minimum_degree_order(4, p.col_ptr(), p.row_idx()).unwrap();
        let mut sorted = amd.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, [0, 1, 2, 3]);
        let mut solutions = Vec::new();
        for order in [None, Some(vec![3, 2, 1, 0]), Some(amd)] {
            let mut s =
                SpdSolver::with_ordering(4, p.col_ptr(), p.row_idx(), order.as_deref()).unwrap();
            s.factor(&values).unwrap();
            let mut x = b.to_vec();
            s.solve_in_place(&mut x).unwrap();
            solutions.push(x);
        }
        for x in &solutions[1..] {
            for (a, b) in x.iter().zip(&solutions[0]) {
                assert!((a - b).abs() < 1e-13);
            }
        }
        assert!(
            SpdSolver::with_ordering(4, p.col_ptr(), p.row_idx(), Some(&[0, 1, 1, 3])).is_err()
        );
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert!(ElementPattern::new(2, [&[0u32, 2][..]]).is_err());
        assert!(ElementPattern::new(2, [&[1u32, 1][..]]).is_err());
        assert!(SpdSolver::new(2, &[0, 1], &[0]).is_err());
        assert!(SpdSolver::new(2, &[0, 1, 2], &[1, 0]).is_err());
        // An untouched unknown leaves a zero diagonal: singular, reported by the factorization.
        let p = ElementPattern::new(2, [&[0u32][..]]).unwrap();
        let mut s = SpdSolver::for_pattern(&p).unwrap();
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&[1.0], &mut v);
        assert!(s.factor(&v).is_err());
        let mut b = vec![1.0, 1.0];
        assert!(s.solve_in_place(&mut b).is_err());
        // Indefinite.
        let p = ElementPattern::new(2, [&[0u32, 1][..]]).unwrap();
        let mut s = SpdSolver::for_pattern(&p).unwrap();
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&[1.0, 2.0, 1.0], &mut v);
        assert!(s.factor(&v).is_err());
    }
}
