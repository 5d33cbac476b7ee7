//! The sparsity pattern of a mesh stiffness matrix, with Dirichlet (fixed) vertices eliminated.

use rayon::prelude::*;

const NONE: u32 = u32::MAX;

/// Sparsity pattern of `M` restricted to the free vertices (lower triangle, CSC, diagonal first
/// in each column), built once per mesh connectivity and set of fixed vertices.
///
/// Face edge weights are given per face corner: `w[f][c]` is the weight of the edge opposite
/// corner `c` of face `f` (for the cotangent Laplacian, `½ cot` of the angle at `c`).
#[derive(Debug, Clone)]
pub struct StiffnessPattern {
    n_unknowns: usize,
    unknown_of: Vec<u32>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// For each stored entry: up to two face corners (`3 f + c`) whose weights sum into it;
    /// `NONE` on diagonal entries.
    entry_src: Vec<[u32; 2]>,
    /// Position of each unknown's diagonal entry in the value array.
    diag_pos: Vec<usize>,
    /// CSR over unknowns: the face corners (`3 f + c`) of every edge incident to the unknown.
    diag_src_ptr: Vec<usize>,
    diag_src: Vec<u32>,
    /// CSR over unknowns: (face corner, fixed neighbour) couplings moved to the right-hand side.
    fixed_ptr: Vec<usize>,
    fixed_src: Vec<(u32, u32)>,
}

impl StiffnessPattern {
    /// Analyses the connectivity `faces` of a mesh with `n_vertices` vertices. Vertices with
    /// `fixed[v] == true` are eliminated (Dirichlet conditions); `fixed = None` keeps all.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]], fixed: Option<&[bool]>) -> Self {
        let is_fixed = |v: u32| fixed.is_some_and(|f| f[v as usize]);
        let mut unknown_of = vec![NONE; n_vertices];
        let mut n_unknowns = 0usize;
        for (v, u) in unknown_of.iter_mut().enumerate() {
            if !is_fixed(v as u32) {
                *u = n_unknowns as u32;
                n_unknowns += 1;
            }
        }
        // Directed half-edge records (lower unknown, higher unknown, corner) for free-free edges;
        // (unknown, fixed vertex, corner) for free-fixed ones; (unknown, corner) for diagonals.
        let mut offdiag: Vec<(u32, u32, u32)> = Vec::with_capacity(faces.len() * 3);
        let mut fixed_rec: Vec<(u32, u32, u32)> = Vec::new();
        let mut diag_rec: Vec<(u32, u32)> = Vec::with_capacity(faces.len() * 6);
        for (f, face) in faces.iter().enumerate() {
            for c in 0..3 {
                let corner = (3 * f + c) as u32;
                let a = face[(c + 1) % 3];
                let b = face[(c + 2) % 3];
                let (ua, ub) = (unknown_of[a as usize], unknown_of[b as usize]);
                if ua != NONE {
                    diag_rec.push((ua, corner));
                }
                if ub != NONE {
                    diag_rec.push((ub, corner));
                }
                match (ua != NONE, ub != NONE) {
                    (true, true) => offdiag.push((ua.max(ub), ua.min(ub), corner)),
                    (true, false) => fixed_rec.push((ua, b, corner)),
                    (false, true) => fixed_rec.push((ub, a, corner)),
                    (false, false) => {}
                }
            }
        }
        // Sort by (column, row): CSC of the lower triangle (row >= column).
        offdiag.par_sort_unstable_by_key(|&(r, c, k)| (c, r, k));
        diag_rec.par_sort_unstable();
        fixed_rec.par_sort_unstable();

        let mut col_ptr = Vec::with_capacity(n_unknowns + 1);
        let mut row_idx = Vec::with_capacity(n_unknowns + offdiag.len() / 2);
        let mut entry_src = Vec::with_capacity(row_idx.capacity());
        let mut diag_pos = Vec::with_capacity(n_unknowns);
        let mut k = 0usize;
        for col in 0..n_unknowns as u32 {
            col_ptr.push(row_idx.len());
            diag_pos.push(row_idx.len());
            row_idx.push(col as usize);
            entry_src.push([NONE, NONE]);
            while k < offdiag.len() && offdiag[k].1 == col {
                let row = offdiag[k].0;
                let mut src = [offdiag[k].2, NONE];
                k += 1;
                if k < offdiag.len() && offdiag[k].1 == col && offdiag[k].0 == row {
                    src[1] = offdiag[k].2;
                    k += 1;
                    // A third face on the same edge cannot happen on a manifold mesh; fold any
                    // extra contributions would be wrong, so skip them (validation rejects them).
                    while k < offdiag.len() && offdiag[k].1 == col && offdiag[k].0 == row {
                        k += 1;
                    }
                }
                row_idx.push(row as usize);
                entry_src.push(src);
            }
        }
        col_ptr.push(row_idx.len());

        let (diag_src_ptr, diag_src) = csr(n_unknowns, &diag_rec, |r| (r.0, r.1));
        let (fixed_ptr, fixed_src) = csr(n_unknowns, &fixed_rec, |r| (r.0, (r.2, r.1)));
        Self {
            n_unknowns,
            unknown_of,
            col_ptr,
            row_idx,
            entry_src,
            diag_pos,
            diag_src_ptr,
            diag_src,
            fixed_ptr,
            fixed_src,
        }
    }

    /// Number of unknowns (free vertices).
    pub fn n_unknowns(&self) -> usize {
        self.n_unknowns
    }
    /// Index of vertex `v` among the unknowns, or `None` if it is fixed.
    pub fn unknown_of(&self, v: usize) -> Option<usize> {
        let u = self.unknown_of[v];
        (u != NONE).then_some(u as usize)
    }
    /// The vertex-to-unknown map (`u32::MAX` for fixed vertices).
    pub fn unknown_map(&self) -> &[u32] {
        &self.unknown_of
    }
    /// Column pointers of the lower-triangular CSC structure.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }
    /// Row indices of the lower-triangular CSC structure.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Fills `values` (length [`nnz`](Self::nnz)) with `M_ij = -Σ w` off the diagonal and
    /// `M_ii = Σ_j w(ij) + diag_extra[vertex]` on it. `weights[f][c]` is the weight of the
    /// edge opposite corner `c` of face `f`; `diag_extra` is indexed by vertex (or empty).
    pub fn assemble(&self, weights: &[[f64; 3]], diag_extra: &[f64], values: &mut [f64]) {
        let w = |corner: u32| -> f64 {
            let f = (corner / 3) as usize;
            weights[f][(corner % 3) as usize]
        };
        values
            .par_iter_mut()
            .zip(self.entry_src.par_iter())
            .for_each(|(v, src)| {
                *v = match *src {
                    [NONE, _] => 0.0,
                    [a, NONE] => -w(a),
                    [a, b] => -(w(a) + w(b)),
                };
            });
        let diag: Vec<f64> = (0..self.n_unknowns)
            .into_par_iter()
            .map(|u| {
                self.diag_src[self.diag_src_ptr[u]..self.diag_src_ptr[u + 1]]
                    .iter()
                    .map(|&c| w(c))
                    .sum::<f64>()
            })
            .collect();
        if diag_extra.is_empty() {
            for (u, d) in diag.into_iter().enumerate() {
                values[self.diag_pos[u]] = d;
            }
        } else {
            let mut vertex_of = vec![0usize; self.n_unknowns];
            for (v, &u) in self.unknown_of.iter().enumerate() {
                if u != NONE {
                    vertex_of[u as usize] = v;
                }
            }
            for (u, d) in diag.into_iter().enumerate() {
                values[self.diag_pos[u]] = d + diag_extra[vertex_of[u]];
            }
        }
    }

    /// Right-hand side contribution of the fixed vertices: `b_u = Σ w(uj) x_j` over fixed
    /// neighbours `j` of unknown `u`, for one coordinate `x` indexed by vertex.
    pub fn fixed_rhs(&self, weights: &[[f64; 3]], x: &[f64]) -> Vec<f64> {
        (0..self.n_unknowns)
            .into_par_iter()
            .map(|u| {
                self.fixed_src[self.fixed_ptr[u]..self.fixed_ptr[u + 1]]
                    .iter()
                    .map(|&(corner, j)| {
                        weights[(corner / 3) as usize][(corner % 3) as usize] * x[j as usize]
                    })
                    .sum()
            })
            .collect()
    }

    /// Matrix-vector product `y = M x` with the values from [`assemble`](Self::assemble)
    /// (symmetric: the stored lower triangle is used both ways). Indexed by unknown.
    #[cfg(test)]
    pub fn mul(&self, values: &[f64], x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n_unknowns];
        for col in 0..self.n_unknowns {
            let range = self.col_ptr[col]..self.col_ptr[col + 1];
            for (&row, &v) in self.row_idx[range.clone()].iter().zip(&values[range]) {
                y[row] += v * x[col];
                if row != col {
                    y[col] += v * x[row];
                }
            }
        }
        y
    }
}

/// Groups records sorted by their first key into CSR form.
fn csr<R, T: Copy>(
    n: usize,
    records: &[R],
    key_val: impl Fn(&R) -> (u32, T),
) -> (Vec<usize>, Vec<T>) {
    let mut ptr = vec![0usize; n + 1];
    let mut vals = Vec::with_capacity(records.len());
    for r in records {
        let (k, v) = key_val(r);
        ptr[k as usize + 1] += 1;
        vals.push(v);
    }
    for i in 0..n {
        ptr[i + 1] += ptr[i];
    }
    (ptr, vals)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles forming the unit square: (0,1,2), (0,2,3).
    fn square() -> Vec<[u32; 3]> {
        vec![[0, 1, 2], [0, 2, 3]]
    }

    fn dense(p: &StiffnessPattern, values: &[f64]) -> Vec<Vec<f64>> {
        let n = p.n_unknowns();
        let mut m = vec![vec![0.0; n]; n];
        let ptr = p.col_ptr();
        for (col, range) in ptr.windows(2).enumerate() {
            let rows = &p.row_idx()[range[0]..range[1]];
            for (&row, &v) in rows.iter().zip(&values[range[0]..range[1]]) {
                m[row][col] = v;
                m[col][row] = v;
            }
        }
        m
    }

    #[test]
    fn assembles_edge_weights_and_zero_row_sums() {
        let faces = square();
        let p = StiffnessPattern::new(4, &faces, None);
        // Unit weights on every edge: the graph Laplacian.
        let w = vec![[1.0; 3]; 2];
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[], &mut v);
        let m = dense(&p, &v);
        // Edge 0-2 (the diagonal) is shared by both faces: weight 2.
        assert_eq!(m[0][2], -2.0);
        assert_eq!(m[0][1], -1.0);
        assert_eq!(m[1][3], 0.0);
        for row in &m {
            assert!(row.iter().sum::<f64>().abs() < 1e-15);
        }
        assert_eq!(m[0][0], 4.0);
    }

    #[test]
    fn eliminates_fixed_vertices_into_rhs() {
        let faces = square();
        let fixed = [true, false, true, false];
        let p = StiffnessPattern::new(4, &faces, Some(&fixed));
        assert_eq!(p.n_unknowns(), 2);
        assert_eq!(p.unknown_of(1), Some(0));
        assert_eq!(p.unknown_of(0), None);
        let w = vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[10.0, 20.0, 30.0, 40.0], &mut v);
        let m = dense(&p, &v);
        // Vertex 1: edges (1,2) opposite corner 0 of face 0 (w=1) and (0,1) opposite corner 2 (w=3).
        assert_eq!(m[0][0], 1.0 + 3.0 + 20.0);
        // Vertex 3: edges (2,3) opp. corner 0 of face 1 (w=4), (3,0) opp. corner 1 (w=5).
        assert_eq!(m[1][1], 4.0 + 5.0 + 40.0);
        assert_eq!(m[0][1], 0.0);
        let b = p.fixed_rhs(&w, &[1.0, 0.0, 2.0, 0.0]);
        assert_eq!(b, vec![1.0 * 2.0 + 3.0 * 1.0, 4.0 * 2.0 + 5.0 * 1.0]);
    }

    #[test]
    fn mul_matches_dense() {
        let faces = square();
        let p = StiffnessPattern::new(4, &faces, None);
        let w = vec![[0.5, 1.5, 2.0], [1.0, 0.25, 3.0]];
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[1.0; 4], &mut v);
        let m = dense(&p, &v);
        let x = [1.0, -2.0, 3.0, 0.5];
        let y = p.mul(&v, &x);
        for i in 0..4 {
            let e: f64 = (0..4).map(|j| m[i][j] * x[j]).sum();
            assert!((y[i] - e).abs() < 1e-12);
        }
    }
}
