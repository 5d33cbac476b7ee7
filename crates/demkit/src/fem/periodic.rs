//! The finite-element operators on the flat torus (TDEM paper (13)–(21)): every face of a
//! [`FlatTorusMap`] is drawn at its corners' lattice translations, so the per-face quantities —
//! areas, cotangent weights, the face gradient (19) — are those of ordinary planar triangles,
//! and assembling them on the vertex indices makes the mass matrix, the Laplacian and W^FV
//! periodic by construction: no seam vertices are duplicated and no rows are copied.

use super::{cotangent_weights, face_gradient};
use crate::geometry::signed_areas_2d;
use crate::geometry::torus::FlatTorusMap;
use crate::linalg::{SparseCholesky, StiffnessPattern};
use crate::{Error, Result};
use std::cell::RefCell;

/// The faces of a flat torus map unfolded into the plane: three points per face, face `f`
/// being `[3f, 3f + 1, 3f + 2]`.
#[derive(Debug, Clone)]
pub struct UnfoldedFaces {
    /// The planar corners of every face (z = 0).
    pub points: Vec<[f64; 3]>,
    /// `[3f, 3f + 1, 3f + 2]` for every face `f`.
    pub faces: Vec<[u32; 3]>,
}

impl UnfoldedFaces {
    /// Unfolds `map` (faces `faces`, periods `period`).
    pub fn new(map: &FlatTorusMap, faces: &[[u32; 3]], period: [f64; 2]) -> Self {
        let (points, faces) = map.unfolded(faces, period);
        Self { points, faces }
    }

    /// Signed planar area of every face (positive when counter-clockwise).
    pub fn signed_areas(&self) -> Vec<f64> {
        signed_areas_2d(&self.points, &self.faces)
    }

    /// The cotangent weights of every face, per corner (4.23): the periodic Laplacian when
    /// assembled on the vertex indices.
    pub fn cotangent_weights(&self) -> Vec<[f64; 3]> {
        cotangent_weights(&self.points, &self.faces)
    }

    /// The face gradient (19) of the vertex function `values` (one value per vertex of the
    /// torus mesh `faces`).
    pub fn gradient(&self, faces: &[[u32; 3]], values: &[f64]) -> Vec<[f64; 3]> {
        let corner_values: Vec<f64> = faces
            .iter()
            .flat_map(|f| f.map(|v| values[v as usize]))
            .collect();
        face_gradient(&self.points, &self.faces, &corner_values)
    }
}

/// The weighted Laplace system of a periodic map: the points `X` minimising
/// `Σ_T Σ_edges w |(X_a + s_a) − (X_b + s_b)|²`, where `s` is the translation at which each face
/// corner is drawn, with the `pinned` vertices held at given points. One sparsity pattern and
/// symbolic Cholesky analysis per connectivity; each [`solve`](Self::solve) refactors
/// numerically. The periodic harmonic map of a genus-one surface (cotangent weights of the
/// surface) and the periodic linear Beltrami solver (generalized Laplacian weights) are this
/// system with different weights.
#[derive(Debug)]
pub struct PeriodicSystem {
    pattern: StiffnessPattern,
    cholesky: RefCell<SparseCholesky>,
    pinned: Vec<bool>,
    values: RefCell<Vec<f64>>,
}

impl PeriodicSystem {
    /// Analyses `faces` on `n_vertices` vertices with the vertices `pinned` eliminated (at least
    /// one per connected surface: the system is invariant under translations).
    pub fn new(n_vertices: usize, faces: &[[u32; 3]], pinned: &[bool]) -> Result<Self> {
        let pattern = StiffnessPattern::new(n_vertices, faces, Some(pinned));
        let cholesky = RefCell::new(SparseCholesky::for_stiffness(&pattern)?);
        let values = RefCell::new(vec![0.0; pattern.nnz()]);
        Ok(Self {
            pattern,
            cholesky,
            pinned: pinned.to_vec(),
            values,
        })
    }

    /// Solves for the per-corner edge weights `weights` (entry `c` of face `f` weighs the edge
    /// opposite corner `c`), the corner translations `shift(f, k)` and the pinned vertices at
    /// `pinned_at[v]` (other entries ignored). Setting the gradient to zero,
    /// `Σ w (X_a + s_a − X_b − s_b) = 0` at every free vertex `a`: each edge adds
    /// `w (s_b − s_a)` to the right-hand side of `a` and the opposite to `b`.
    ///
    /// Errors: [`Error::Numerical`] when the matrix is not positive definite or the solution
    /// is not finite.
    pub fn solve(
        &self,
        faces: &[[u32; 3]],
        weights: &[[f64; 3]],
        shift: impl Fn(usize, usize) -> [f64; 2],
        pinned_at: &[[f64; 2]],
    ) -> Result<Vec<[f64; 2]>> {
        let mut values = self.values.borrow_mut();
        self.pattern.assemble(weights, &[], &mut values);
        let mut cholesky = self.cholesky.borrow_mut();
        cholesky.factor(&values)?;
        let n = self.pattern.n_unknowns();
        let unknown = self.pattern.unknown_map();
        let coordinate = |d: usize| pinned_at.iter().map(|p| p[d]).collect::<Vec<f64>>();
        let mut rhs = self.pattern.fixed_rhs(weights, &coordinate(0));
        rhs.extend(self.pattern.fixed_rhs(weights, &coordinate(1)));
        for (f, (t, wf)) in faces.iter().zip(weights).enumerate() {
            let s = [shift(f, 0), shift(f, 1), shift(f, 2)];
            for (c, &w) in wf.iter().enumerate() {
                let (a, b) = ((c + 1) % 3, (c + 2) % 3);
                let flow = [w * (s[b][0] - s[a][0]), w * (s[b][1] - s[a][1])];
                for (corner, sign) in [(a, 1.0), (b, -1.0)] {
                    let u = unknown[t[corner] as usize];
                    if u != u32::MAX {
                        rhs[u as usize] += sign * flow[0];
                        rhs[n + u as usize] += sign * flow[1];
                    }
                }
            }
        }
        cholesky.solve_many_in_place(&mut rhs, 2)?;
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err(Error::Numerical(
                "the periodic Laplace system has no finite solution".into(),
            ));
        }
        Ok((0..unknown.len())
            .map(|v| match unknown[v] {
                u32::MAX if self.pinned[v] => pinned_at[v],
                u32::MAX => [0.0, 0.0],
                u => [rhs[u as usize], rhs[n + u as usize]],
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{VertexFaces, lumped_mass};
    use crate::generate::torus;
    use crate::geometry::torus::Torus;

    fn flat_torus(n: usize, m: usize) -> (FlatTorusMap, Vec<[u32; 3]>, Torus) {
        let t = Torus::new(3.0, 1.0).unwrap();
        let mesh = torus(3.0, 1.0, n, m).unwrap();
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, &t);
        (map, mesh.faces, t)
    }

    #[test]
    fn unfolded_faces_tile_the_period_rectangle() {
        let (map, faces, t) = flat_torus(24, 12);
        let u = UnfoldedFaces::new(&map, &faces, t.periods());
        let areas = u.signed_areas();
        assert!(areas.iter().all(|&a| a > 0.0));
        let [a, b] = t.periods();
        let total: f64 = areas.iter().sum();
        assert!((total - a * b).abs() < 1e-9 * a * b, "{total} vs {}", a * b);
        // The lumped mass sums to the same area.
        let mass = lumped_mass(map.points.len(), &faces, &areas);
        assert!((mass.iter().sum::<f64>() - a * b).abs() < 1e-9 * a * b);
    }

    #[test]
    fn periodic_laplacian_annihilates_constants_and_periodic_modes_are_eigenvectors() {
        // On the flat grid torus every row of L sums to zero (constants do not diffuse, also
        // across the seams), and the periodic mode cos(u/R) satisfies L f ≈ λ A f, λ = 1/R².
        let (map, faces, t) = flat_torus(48, 16);
        let u = UnfoldedFaces::new(&map, &faces, t.periods());
        let w = u.cotangent_weights();
        let n = map.points.len();
        let apply = |x: &[f64]| {
            let mut out = vec![0.0; n];
            for (f, wf) in faces.iter().zip(&w) {
                for c in 0..3 {
                    let (a, b) = (f[(c + 1) % 3] as usize, f[(c + 2) % 3] as usize);
                    out[a] += wf[c] * (x[a] - x[b]);
                    out[b] += wf[c] * (x[b] - x[a]);
                }
            }
            out
        };
        for v in apply(&vec![1.0; n]) {
            assert!(v.abs() < 1e-12);
        }
        let areas = u.signed_areas();
        let mass = lumped_mass(n, &faces, &areas);
        let f: Vec<f64> = map.points.iter().map(|p| (p[0] / t.major).cos()).collect();
        let lf = apply(&f);
        let lambda = 1.0 / (t.major * t.major);
        for i in 0..n {
            assert!((lf[i] - lambda * mass[i] * f[i]).abs() < 0.02 * lambda * mass[i]);
        }
    }

    #[test]
    fn gradient_of_a_periodic_function_is_exact_across_the_seam() {
        // g(u, v) = sin(v/r): its face gradient is (0, cos(v/r)/r) up to O(h), also on the
        // faces that straddle v = ±πr, and W^FV keeps it.
        let (map, faces, t) = flat_torus(30, 40);
        let u = UnfoldedFaces::new(&map, &faces, t.periods());
        let values: Vec<f64> = map.points.iter().map(|p| (p[1] / t.minor).sin()).collect();
        let g = u.gradient(&faces, &values);
        let areas = u.signed_areas();
        let gv = VertexFaces::new(map.points.len(), &faces).apply_vec(&areas, &g);
        for (p, gv) in map.points.iter().zip(&gv) {
            let want = (p[1] / t.minor).cos() / t.minor;
            assert!(
                gv[0].abs() < 1e-9 && (gv[1] - want).abs() < 0.02,
                "{p:?} {gv:?}"
            );
        }
    }
}
