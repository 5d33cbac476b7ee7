//! Dirichlet problems of a weighted Laplacian on a fixed connectivity: find the planar map
//! whose free vertices satisfy `Σ_j w_ij (x_j − x_i) = 0` with the fixed vertices at given
//! points. With cotangent weights this is the harmonic map (DEM paper (4.12)), with uniform
//! weights Tutte's embedding ((4.13); bijective onto a convex boundary), with the generalized
//! Laplacian of (3.11) the linear Beltrami solver (DEQ paper §3.2). The sparsity pattern and its
//! symbolic Cholesky analysis are computed once; each solve refactors numerically.

use crate::Result;
use crate::linalg::{SparseCholesky, StiffnessPattern, VertexOrder};
use std::cell::RefCell;

/// A symmetric weighted Laplacian restricted to the free vertices of one connectivity.
#[derive(Debug)]
pub struct DirichletSystem {
    fixed: Vec<bool>,
    pattern: StiffnessPattern,
    cholesky: RefCell<SparseCholesky>,
}

/// Tutte's weights: ½ per face corner, so every interior edge weighs 1 (DEM paper (4.13)).
pub fn uniform_weights(n_faces: usize) -> Vec<[f64; 3]> {
    vec![[0.5; 3]; n_faces]
}

impl DirichletSystem {
    /// Prepares the system of `faces` on `n_vertices` vertices with the vertices where
    /// `fixed[v]` holds as Dirichlet vertices (at least one per connected component of the
    /// free vertices). Vertices no face uses must be fixed.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]], fixed: &[bool]) -> Result<Self> {
        Self::in_order(n_vertices, faces, fixed, None)
    }

    /// As [`new`](Self::new), eliminating the free vertices in the connectivity's `order`
    /// when one is given ([`VertexOrder`]).
    pub fn in_order(
        n_vertices: usize,
        faces: &[[u32; 3]],
        fixed: &[bool],
        order: Option<&VertexOrder>,
    ) -> Result<Self> {
        let pattern = StiffnessPattern::new(n_vertices, faces, Some(fixed));
        let cholesky = RefCell::new(SparseCholesky::for_stiffness_in(&pattern, order)?);
        Ok(Self {
            fixed: fixed.to_vec(),
            pattern,
            cholesky,
        })
    }

    /// True when vertex `v` is a Dirichlet vertex.
    pub fn is_fixed(&self, v: usize) -> bool {
        self.fixed[v]
    }

    /// Solves with symmetric per-face corner weights `weights[f][c]` (the weight of the edge
    /// opposite corner `c`) and the fixed vertices at `values[v]` (other entries are ignored).
    /// Returns the planar position of every vertex (z = 0).
    pub fn solve(&self, weights: &[[f64; 3]], values: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        let mut matrix = vec![0.0; self.pattern.nnz()];
        self.pattern.assemble(weights, &[], &mut matrix);
        let mut cholesky = self.cholesky.borrow_mut();
        cholesky.factor(&matrix)?;
        let bx: Vec<f64> = values.iter().map(|p| p[0]).collect();
        let by: Vec<f64> = values.iter().map(|p| p[1]).collect();
        let n = self.pattern.n_unknowns();
        let mut rhs = self.pattern.fixed_rhs(weights, &bx);
        rhs.extend(self.pattern.fixed_rhs(weights, &by));
        cholesky.solve_many_in_place(&mut rhs, 2)?;
        let map = self.pattern.unknown_map();
        Ok((0..values.len())
            .map(|v| {
                if self.fixed[v] {
                    [values[v][0], values[v][1], 0.0]
                } else {
                    let u = map[v] as usize;
                    [rhs[u], rhs[n + u], 0.0]
                }
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::cotangent_weights;
    use crate::generate_fixtures::grid;

    #[test]
    fn harmonic_extension_reproduces_a_linear_map() {
        // Linear functions are harmonic: with the boundary of a planar grid sent by an affine
        // map, the cotangent-weight solution is that affine map everywhere.
        let (pos, faces, boundary) = grid(5, 0.2);
        let fixed = boundary;
        let affine = |p: [f64; 3]| [2.0 * p[0] - p[1] + 0.5, 0.3 * p[0] + p[1], 0.0];
        let values: Vec<[f64; 3]> = pos.iter().map(|&p| affine(p)).collect();
        let sys = DirichletSystem::new(pos.len(), &faces, &fixed).unwrap();
        let out = sys
            .solve(&cotangent_weights(&pos, &faces), &values)
            .unwrap();
        for (p, q) in pos.iter().zip(&out) {
            let e = affine(*p);
            assert!((e[0] - q[0]).abs() < 1e-12 && (e[1] - q[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn uniform_weights_put_a_vertex_at_its_neighbours_mean() {
        let (pos, faces, boundary) = grid(4, 0.0);
        let fixed = boundary;
        let sys = DirichletSystem::new(pos.len(), &faces, &fixed).unwrap();
        let out = sys.solve(&uniform_weights(faces.len()), &pos).unwrap();
        // Each free vertex is the mean of its neighbours (every interior edge weighs 1).
        let mut sum = vec![[0.0f64; 3]; pos.len()];
        let mut count = vec![0.0f64; pos.len()];
        for [a, b] in crate::mesh::topology::edges(&faces) {
            let (a, b) = (a as usize, b as usize);
            for (i, j) in [(a, b), (b, a)] {
                sum[i][0] += out[j][0];
                sum[i][1] += out[j][1];
                count[i] += 1.0;
            }
        }
        for v in (0..pos.len()).filter(|&v| !fixed[v]) {
            assert!((sum[v][0] / count[v] - out[v][0]).abs() < 1e-12);
            assert!((sum[v][1] / count[v] - out[v][1]).abs() < 1e-12);
        }
    }
}
