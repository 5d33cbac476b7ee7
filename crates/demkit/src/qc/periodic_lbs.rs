//! The linear Beltrami solver on the flat torus: the map with a given Beltrami coefficient whose
//! faces keep their lattice translations, i.e. the minimizer of the generalized Dirichlet energy
//! `Σ_T Σ_edges w |(X_a + s_a) − (X_b + s_b)|²` over the vertex points `X` (the `s` being the
//! corners' period translations), with one vertex pinned against the translations of the torus.
//! It is the TDEM paper's mesh overlap correction (Alg. 1 line 7) for a periodic map: the
//! periodicity (24)–(25) holds by construction rather than by fixing the cut's vertices.

use super::generalized_laplacian_weights;
use crate::Result;
use crate::fem::UnfoldedFaces;
use crate::geometry::torus::FlatTorusMap;
use crate::linalg::{CachedCholesky, StiffnessPattern};
use num_complex::Complex64;

/// LBS on one genus-one connectivity, with vertex 0 pinned.
#[derive(Debug)]
pub struct PeriodicBeltramiSolver {
    faces: Vec<[u32; 3]>,
    pattern: StiffnessPattern,
    cholesky: CachedCholesky,
}

impl PeriodicBeltramiSolver {
    /// Analyses the connectivity `faces` on `n_vertices` vertices.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Self> {
        let mut pinned = vec![false; n_vertices];
        if let Some(p) = pinned.first_mut() {
            *p = true;
        }
        let pattern = StiffnessPattern::new(n_vertices, faces, Some(&pinned));
        let cholesky = CachedCholesky::new(&pattern)?;
        Ok(Self {
            faces: faces.to_vec(),
            pattern,
            cholesky,
        })
    }

    /// The flat torus map with Beltrami coefficient `mu` (per face, |μ| < 1) relative to the
    /// flat map `source` (unfolded), with the lattice translations `offsets` of the faces'
    /// corners (periods `period`) and vertex 0 at `pinned_at`.
    pub fn solve(
        &self,
        source: &UnfoldedFaces,
        mu: &[Complex64],
        offsets: &[[[i32; 2]; 3]],
        period: [f64; 2],
        pinned_at: [f64; 2],
    ) -> Result<FlatTorusMap> {
        let n_vertices = self.pattern.unknown_map().len();
        let w = generalized_laplacian_weights(&source.points, &source.faces, mu);
        let mut values = vec![0.0; self.pattern.nnz()];
        self.pattern.assemble(&w, &[], &mut values);
        let factor = self.cholesky.factor(&self.pattern, &values)?;
        let n = self.pattern.n_unknowns();
        let mut pinned_x = vec![0.0; n_vertices];
        let mut pinned_y = vec![0.0; n_vertices];
        pinned_x[0] = pinned_at[0];
        pinned_y[0] = pinned_at[1];
        let mut rhs = self.pattern.fixed_rhs(&w, &pinned_x);
        rhs.extend(self.pattern.fixed_rhs(&w, &pinned_y));
        // The period translations: ∂E/∂X_a = Σ w (X_a + s_a − X_b − s_b) = 0, so each edge adds
        // w (s_b − s_a) to the right-hand side of a (and the opposite to b).
        let map = self.pattern.unknown_map();
        for ((f, wf), o) in self.faces.iter().zip(&w).zip(offsets) {
            let shift = |k: usize| [o[k][0] as f64 * period[0], o[k][1] as f64 * period[1]];
            for (c, &weight) in wf.iter().enumerate() {
                let (a, b) = ((c + 1) % 3, (c + 2) % 3);
                let (sa, sb) = (shift(a), shift(b));
                for (corner, sign) in [(a, 1.0), (b, -1.0)] {
                    let u = map[f[corner] as usize];
                    if u != u32::MAX {
                        let u = u as usize;
                        rhs[u] += sign * weight * (sb[0] - sa[0]);
                        rhs[n + u] += sign * weight * (sb[1] - sa[1]);
                    }
                }
            }
        }
        factor.solve_many_in_place(&mut rhs, 2);
        let points = (0..n_vertices)
            .map(|v| match map[v] {
                u32::MAX => pinned_at,
                u => [rhs[u as usize], rhs[n + u as usize]],
            })
            .collect();
        Ok(FlatTorusMap {
            points,
            offsets: offsets.to_vec(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::torus;
    use crate::geometry::torus::Torus;

    #[test]
    fn a_constant_coefficient_gives_back_the_source() {
        // With a constant coefficient the equations ∇·(A∇u) = 0 are solved by every affine
        // function, and the periods fix it: the result is the source itself, for μ = 0 and for
        // any constant μ (z + k z̄ would change the periods, so it is not a periodic map).
        let t = Torus::new(3.0, 1.0).unwrap();
        let mesh = torus(3.0, 1.0, 36, 12).unwrap();
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, &t);
        let source = UnfoldedFaces::new(&map, &mesh.faces, t.periods());
        let solver = PeriodicBeltramiSolver::new(mesh.n_vertices(), &mesh.faces).unwrap();
        for k in [Complex64::new(0.0, 0.0), Complex64::new(0.3, -0.2)] {
            let mu = vec![k; mesh.n_faces()];
            let out = solver
                .solve(&source, &mu, &map.offsets, t.periods(), map.points[0])
                .unwrap();
            for (a, b) in out.points.iter().zip(&map.points) {
                assert!((a[0] - b[0]).hypot(a[1] - b[1]) < 1e-9, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn smooths_a_perturbed_map_back_to_an_embedding() {
        // Push a band of vertices along u until triangles fold, then rebuild from the
        // truncated μ of the folded map: the result has no flipped face.
        let t = Torus::new(2.0, 1.0).unwrap();
        let mesh = torus(2.0, 1.0, 40, 20).unwrap();
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, &t);
        let period = t.periods();
        let mut bent = map.clone();
        for p in bent.points.iter_mut() {
            p[0] += 1.5 * (-((p[0] - 3.0) / 0.3).powi(2)).exp();
        }
        assert!(bent.count_flipped(&mesh.faces, period) > 0);
        let source = UnfoldedFaces::new(&map, &mesh.faces, period);
        let target = UnfoldedFaces::new(&bent, &mesh.faces, period);
        let mu: Vec<Complex64> =
            crate::qc::beltrami_coefficient(&source.points, &target.points, &source.faces)
                .into_iter()
                .map(|m| crate::qc::truncate(m, 0.1))
                .collect();
        let solver = PeriodicBeltramiSolver::new(mesh.n_vertices(), &mesh.faces).unwrap();
        let out = solver
            .solve(&source, &mu, &map.offsets, period, bent.points[0])
            .unwrap();
        assert_eq!(out.count_flipped(&mesh.faces, period), 0);
    }
}
