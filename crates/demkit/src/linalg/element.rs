//! An element-by-element assembler whose gather is parallel: [`ElementPattern`] stores the
//! matrix `K = Σ_e Sₑᵀ Kₑ Sₑ` assembled from small dense symmetric element matrices `Kₑ` over
//! lists of unknowns (`Sₑ` selects element `e`'s unknowns); the lower triangle of `K` is kept
//! in compressed sparse columns, ready for [`SparseCholesky`](super::SparseCholesky), which
//! factors it after a fill-reducing ordering: approximate minimum degree, or one given by the
//! caller — e.g. expanded from [`minimum_degree_order`](super::minimum_degree_order) of a
//! smaller graph when the unknowns come in blocks per mesh vertex, which is much cheaper to
//! compute.

use crate::{Error, Result};
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
    #[cfg(test)]
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::SparseCholesky;

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
        let mut solver = SparseCholesky::for_pattern(&p).unwrap();
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
    fn bad_input_is_an_error_not_a_panic() {
        assert!(ElementPattern::new(2, [&[0u32, 2][..]]).is_err());
        assert!(ElementPattern::new(2, [&[1u32, 1][..]]).is_err());
    }
}
