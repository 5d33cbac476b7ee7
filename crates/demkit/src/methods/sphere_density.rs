//! Density diffusion on the sphere (SDEM paper §3.1.2): the operators of one iteration, built
//! once per mesh (sparsity pattern and symbolic Cholesky analysis) and refactored numerically
//! every iteration with the current A_n and L_n.

use super::sphere_overlap::tangential;
use crate::Result;
use crate::fem::{VertexFaces, cotangent_weights, face_gradient, lumped_mass};
use crate::geometry::face_areas;
use crate::linalg::{CachedCholesky, StiffnessPattern};
use rayon::prelude::*;

/// The recoupled density of a map (3.22) and the quantities measured on it.
pub(crate) struct Density {
    /// Face areas A(T) of the map.
    pub areas: Vec<f64>,
    /// ρ_V = W^FV (P / A) (3.4).
    pub rho_v: Vec<f64>,
    /// sd(ρ_V) / mean(ρ_V): SDEM's stopping quantity.
    pub sd_over_mean: f64,
}

/// The diffusion operators of one mesh.
pub(crate) struct SphereDiffusion<'a> {
    faces: &'a [[u32; 3]],
    population: &'a [f64],
    incidence: VertexFaces,
    pattern: StiffnessPattern,
    cholesky: CachedCholesky,
}

impl<'a> SphereDiffusion<'a> {
    pub(crate) fn new(n: usize, faces: &'a [[u32; 3]], population: &'a [f64]) -> Result<Self> {
        let pattern = StiffnessPattern::new(n, faces, None);
        let cholesky = CachedCholesky::new(&pattern)?;
        Ok(Self {
            faces,
            population,
            incidence: VertexFaces::new(n, faces),
            pattern,
            cholesky,
        })
    }

    /// The recoupled density of `map` (3.22), (3.4).
    pub(crate) fn measure(&self, map: &[[f64; 3]]) -> Density {
        let areas = face_areas(map, self.faces);
        let rho_f: Vec<f64> = self
            .population
            .par_iter()
            .zip(areas.par_iter())
            .map(|(p, a)| p / a)
            .collect();
        let rho_v = self.incidence.apply(&areas, &rho_f);
        let n = rho_v.len() as f64;
        let mean = rho_v.iter().sum::<f64>() / n;
        // sd of ρ/mean rather than sd(ρ)/mean: squares of tiny densities would underflow.
        let sd_over_mean = (rho_v.iter().map(|x| (x / mean - 1.0).powi(2)).sum::<f64>() / n).sqrt();
        Density {
            areas,
            rho_v,
            sd_over_mean: if sd_over_mean.is_finite() {
                sd_over_mean
            } else {
                f64::INFINITY
            },
        }
    }

    /// The tangential velocity (3.12)–(3.13) after one diffusion step of length `dt` (3.9)
    /// from the density `d` of `map`: `ṽ = −(W^FV ∇ρ) / ρ`, minus its normal component.
    /// `dt = 0` takes the velocity of ρ_V itself.
    pub(crate) fn velocity(&self, map: &[[f64; 3]], d: &Density, dt: f64) -> Result<Vec<[f64; 3]>> {
        let rho = if dt > 0.0 {
            self.diffuse(map, d, dt)?
        } else {
            d.rho_v.clone()
        };
        let grad_f = face_gradient(map, self.faces, &rho);
        let grad_v = self.incidence.apply_vec(&d.areas, &grad_f);
        Ok(grad_v
            .par_iter()
            .zip(rho.par_iter())
            .zip(map.par_iter())
            .map(|((g, r), &p)| tangential([-g[0] / r, -g[1] / r, -g[2] / r], p))
            .collect())
    }

    /// One backward-Euler diffusion step (3.9): `(A + δt L) ρ = A ρ_V`, floored at a thousandth
    /// of the smallest initial value.
    fn diffuse(&self, map: &[[f64; 3]], d: &Density, dt: f64) -> Result<Vec<f64>> {
        let n = map.len();
        let mut w = cotangent_weights(map, self.faces);
        w.par_iter_mut().for_each(|x| *x = x.map(|c| c * dt));
        let mass = lumped_mass(n, self.faces, &d.areas);
        let mut values = vec![0.0; self.pattern.nnz()];
        self.pattern.assemble(&w, &mass, &mut values);
        let factor = self.cholesky.factor(&self.pattern, &values)?;
        let mut rho: Vec<f64> = mass.iter().zip(&d.rho_v).map(|(a, p)| a * p).collect();
        factor.solve_in_place(&mut rho);
        let floor = d.rho_v.iter().cloned().fold(f64::INFINITY, f64::min) * 1e-3;
        for x in rho.iter_mut() {
            if !(*x > floor) {
                *x = floor;
            }
        }
        Ok(rho)
    }
}
