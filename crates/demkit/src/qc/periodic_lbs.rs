//! The linear Beltrami solver on the flat torus: the map with a given Beltrami coefficient whose
//! faces keep their lattice translations, i.e. the minimizer of the generalized Dirichlet energy
//! `Σ_T Σ_edges w |(X_a + s_a) − (X_b + s_b)|²` over the vertex points `X` (the `s` being the
//! corners' period translations), with one vertex pinned against the translations of the torus.
//! It is the TDEM paper's mesh overlap correction (Alg. 1 line 7) for a periodic map: the
//! periodicity (24)–(25) holds by construction rather than by fixing the cut's vertices.

use super::generalized_laplacian_weights;
use crate::Result;
use crate::fem::{PeriodicSystem, UnfoldedFaces};
use crate::geometry::torus::FlatTorusMap;
use num_complex::Complex64;

/// LBS on one genus-one connectivity, with vertex 0 pinned.
#[derive(Debug)]
pub struct PeriodicBeltramiSolver {
    faces: Vec<[u32; 3]>,
    n_vertices: usize,
    system: PeriodicSystem,
}

impl PeriodicBeltramiSolver {
    /// Analyses the connectivity `faces` on `n_vertices` vertices.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Self> {
        let mut pinned = vec![false; n_vertices];
        if let Some(p) = pinned.first_mut() {
            *p = true;
        }
        Ok(Self {
            faces: faces.to_vec(),
            n_vertices,
            system: PeriodicSystem::new(n_vertices, faces, &pinned)?,
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
        let w = generalized_laplacian_weights(&source.points, &source.faces, mu);
        let shift = |f: usize, k: usize| {
            let o = offsets[f][k];
            [o[0] as f64 * period[0], o[1] as f64 * period[1]]
        };
        let mut pinned = vec![[0.0; 2]; self.n_vertices];
        if let Some(p) = pinned.first_mut() {
            *p = pinned_at;
        }
        let points = self.system.solve(&self.faces, &w, shift, &pinned)?;
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
