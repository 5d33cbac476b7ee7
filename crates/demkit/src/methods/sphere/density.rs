//! Density diffusion on the sphere (SDEM paper §3.1.2) or an ellipsoid (EDEM paper §3.2): the
//! operators of one iteration, built once per mesh (sparsity pattern and symbolic Cholesky
//! analysis) and refactored numerically every iteration with the current A_n and L_n.

use crate::Result;
use crate::fem::{DiffusionOperator, REFACTOR_DRIFT, VertexFaces, face_gradient};
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::face_areas;
use crate::linalg::VertexOrder;
use crate::metrics::{log_area_misfit, normalized_variance};
use rayon::prelude::*;

/// The recoupled density of a map (3.22) and the quantities measured on it.
pub(crate) struct Density {
    /// Face areas A(T) of the map.
    pub areas: Vec<f64>,
    /// ρ_V = W^FV (P / A) (3.4).
    pub rho_v: Vec<f64>,
    /// sd(ρ_V) / mean(ρ_V): SDEM's stopping quantity.
    pub sd_over_mean: f64,
    /// The face misfit mean |log((A/ΣA)/(P/ΣP))| ([`log_area_misfit`]).
    pub misfit: f64,
    /// The velocity per unit step taken from this map, kept for the search along it
    /// (`Step::Search`): a retry or a longer move reuses it.
    pub direction: std::cell::RefCell<Option<Vec<[f64; 3]>>>,
}

/// The diffusion operators of one mesh mapped onto one domain.
pub(crate) struct SphereDiffusion<'a> {
    /// Where the maps lie: velocities are taken tangential to it.
    domain: Ellipsoid,
    faces: &'a [[u32; 3]],
    population: &'a [f64],
    incidence: VertexFaces,
    /// Σ P(T) over the faces of each vertex: the numerator of ρ_V ([`Self::measure`]).
    vertex_population: Vec<f64>,
    operator: DiffusionOperator,
}

impl<'a> SphereDiffusion<'a> {
    /// The operators of `faces` on `n` vertices mapped onto `domain`; `order`: the mesh's
    /// elimination order, if the caller has one.
    pub(crate) fn new(
        domain: Ellipsoid,
        n: usize,
        faces: &'a [[u32; 3]],
        population: &'a [f64],
        order: Option<&VertexOrder>,
    ) -> Result<Self> {
        let incidence = VertexFaces::new(n, faces);
        Ok(Self {
            domain,
            faces,
            population,
            vertex_population: incidence.sum(population),
            incidence,
            operator: DiffusionOperator::in_order(n, faces, order)?,
        })
    }

    /// The recoupled density of `map` (3.22), (3.4). W^FV weighs ρ_F = P/A by the areas, so
    /// `ρ_V(v) = Σ A(T) P(T)/A(T) / Σ A(T) = Σ P(T) / Σ A(T)` over the faces of v: the
    /// population sums are the mesh's, and only the area sums change with the map.
    pub(crate) fn measure(&self, map: &[[f64; 3]]) -> Density {
        let areas = face_areas(map, self.faces);
        let (incidence, population) = (&self.incidence, &self.vertex_population);
        let rho_v: Vec<f64> = (0..population.len())
            .into_par_iter()
            .map(|v| {
                let a: f64 = incidence
                    .faces_of(v)
                    .iter()
                    .map(|&f| areas[f as usize])
                    .sum();
                if a > 0.0 { population[v] / a } else { 0.0 }
            })
            .collect();
        let sd_over_mean = normalized_variance(&rho_v).sqrt();
        Density {
            direction: std::cell::RefCell::new(None),
            misfit: log_area_misfit(self.population, &areas),
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
    /// from the density `d` of `map`: `ṽ = −(W^FV ∇ρ) / ρ`, minus its component along the
    /// domain's normal. `dt = 0` takes the velocity of ρ_V itself.
    pub(crate) fn velocity(&self, map: &[[f64; 3]], d: &Density, dt: f64) -> Result<Vec<[f64; 3]>> {
        let (rho, grad_v) = self.diffused_gradient(map, d, dt)?;
        let domain = self.domain;
        Ok(grad_v
            .par_iter()
            .zip(rho.par_iter())
            .zip(map.par_iter())
            .map(|((g, r), &p)| domain.tangential([-g[0] / r, -g[1] / r, -g[2] / r], p))
            .collect())
    }

    /// The density ρ after one diffusion step of length `dt` from the density `d` of `map`
    /// (ρ_V itself for `dt = 0`), and its gradient at the vertices, `W^FV ∇ρ` (3.10)–(3.11).
    pub(crate) fn diffused_gradient(
        &self,
        map: &[[f64; 3]],
        d: &Density,
        dt: f64,
    ) -> Result<(Vec<f64>, Vec<[f64; 3]>)> {
        let rho = if dt > 0.0 {
            self.diffuse(map, d, dt)?
        } else {
            d.rho_v.clone()
        };
        let grad_f = face_gradient(map, self.faces, &rho);
        let grad_v = self.incidence.apply_vec(&d.areas, &grad_f);
        Ok((rho, grad_v))
    }

    /// One backward-Euler diffusion step (3.9), `(A + δt L) ρ = A ρ_V` ([`DiffusionOperator`]),
    /// with the operator of the last map factored while the face areas have drifted from it
    /// by at most [`REFACTOR_DRIFT`] ([`DiffusionOperator::factor_lazily`]).
    fn diffuse(&self, map: &[[f64; 3]], d: &Density, dt: f64) -> Result<Vec<f64>> {
        self.operator
            .factor_lazily(map, &d.areas, dt, REFACTOR_DRIFT)?
            .diffuse(&d.rho_v)
    }

    /// The diffusion operator of this mesh, for other systems on the same connectivity.
    pub(crate) fn operator(&self) -> &DiffusionOperator {
        &self.operator
    }
}
