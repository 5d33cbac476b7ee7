//! The density flow on a circle domain, shared by DEQ and LDEQ (DEQ paper Appendix A): the
//! face and vertex densities, one backward-Euler diffusion step (A.9)–(A.10), the velocity
//! `v = −∇ρ/ρ` (5.8), (5.35) from the face gradients (A.13) averaged at the vertices (A.14,
//! without its area weights, see `DensityFlow::evaluate`), and the circles the boundary
//! vertices live on.
//!
//! The vertex density is the plain average of the face densities around the vertex (the DEM
//! paper's Whitney interpolation (4.27)), not the area-weighted (A.1): with area weights a
//! triangle squeezed by a step loses its say in its corners' density exactly when its density
//! is too high, nothing pushes it open again, and the next steps squeeze it further (measured
//! on an annulus with four density quadrants: the variance of ρ̃ fell to 0.04, then one face
//! collapsed and it jumped to 300).

use crate::Result;
use crate::fem::{DiffusionOperator, VertexFaces, face_gradient};
use crate::geometry::face_areas;
use crate::metrics::normalized_variance;

/// A circle of the circle domain: `|z − center| = radius`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Circle {
    pub center: [f64; 2],
    pub radius: f64,
}

impl Circle {
    /// The unit vector from the centre towards `p` (the outer normal of a hole's domain side
    /// is its opposite).
    pub fn radial(&self, p: [f64; 3]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.center[0], p[1] - self.center[1]);
        let r = dx.hypot(dy);
        if r > 0.0 {
            [dx / r, dy / r]
        } else {
            [1.0, 0.0]
        }
    }

    /// The counter-clockwise unit tangent at `p`.
    pub fn tangent(&self, p: [f64; 3]) -> [f64; 2] {
        let u = self.radial(p);
        [-u[1], u[0]]
    }

    /// The point of the circle nearest to `p` (z = 0).
    pub fn project(&self, p: [f64; 3]) -> [f64; 3] {
        let u = self.radial(p);
        [
            self.center[0] + self.radius * u[0],
            self.center[1] + self.radius * u[1],
            0.0,
        ]
    }
}

/// The boundary of a circle domain: loop 0 is the outer unit circle, the others are holes.
#[derive(Debug, Clone)]
pub(crate) struct CircleBoundary {
    /// Vertex loops, outer first.
    pub loops: Vec<Vec<u32>>,
    /// The circle of each loop.
    pub circles: Vec<Circle>,
    /// The loop of each vertex, `u32::MAX` for interior vertices.
    pub loop_of: Vec<u32>,
}

impl CircleBoundary {
    /// The boundary of `n_vertices` vertices with these loops (outer first) and circles.
    pub fn new(n_vertices: usize, loops: Vec<Vec<u32>>, circles: Vec<Circle>) -> Self {
        let mut loop_of = vec![u32::MAX; n_vertices];
        for (l, lp) in loops.iter().enumerate() {
            for &v in lp {
                loop_of[v as usize] = l as u32;
            }
        }
        Self {
            loops,
            circles,
            loop_of,
        }
    }

    /// The Neumann condition ∇ρ·n = 0 of §5.1.3 on the velocity: the part of `v` pointing
    /// into the nearest circle (out of the domain) is removed at the boundary and tapered
    /// linearly to nothing at distance `layer` from it. The discrete velocity of the first
    /// rings keeps such a part, which the boundary vertices, which only slide, cannot follow:
    /// the triangles between them would be crushed against the circle within a fraction of a
    /// step. Motion away from the boundary is kept, so a triangle squeezed against a circle
    /// can open again.
    pub fn neumann_layer(&self, x: &[[f64; 3]], v: &mut [[f64; 2]], layer: f64) {
        for (p, w) in x.iter().zip(v.iter_mut()) {
            let (mut dist, mut outward) = (f64::INFINITY, [0.0; 2]);
            for (l, c) in self.circles.iter().enumerate() {
                let d = ((p[0] - c.center[0]).hypot(p[1] - c.center[1]) - c.radius).abs();
                if d < dist {
                    dist = d;
                    let u = c.radial(*p);
                    // Out of the domain: away from the centre of the outer circle, towards
                    // the centre of a hole.
                    outward = if l == 0 { u } else { [-u[0], -u[1]] };
                }
            }
            let weight = 1.0 - dist / layer;
            let vn = w[0] * outward[0] + w[1] * outward[1];
            if weight > 0.0 && vn > 0.0 {
                w[0] -= weight * vn * outward[0];
                w[1] -= weight * vn * outward[1];
            }
        }
    }

    /// True for every boundary vertex.
    pub fn is_boundary(&self) -> Vec<bool> {
        self.loop_of.iter().map(|&l| l != u32::MAX).collect()
    }
}

/// What the flow measures on a map.
pub(crate) struct FlowState {
    /// `v = −∇ρ/ρ` at every vertex (x, y).
    pub velocity: Vec<[f64; 2]>,
}

/// The density flow of one mesh and population.
pub(crate) struct DensityFlow<'a> {
    /// Average the face gradients at the vertices with the area weights of (A.14) (LDEQ)
    /// instead of plainly (DEQ).
    pub area_weighted_gradient: bool,
    faces: &'a [[u32; 3]],
    population: &'a [f64],
    incidence: VertexFaces,
    diffusion: DiffusionOperator,
}

impl<'a> DensityFlow<'a> {
    /// Prepares the flow on `faces` over `n_vertices` vertices.
    pub fn new(n_vertices: usize, faces: &'a [[u32; 3]], population: &'a [f64]) -> Result<Self> {
        Ok(Self {
            area_weighted_gradient: false,
            faces,
            population,
            incidence: VertexFaces::new(n_vertices, faces),
            diffusion: DiffusionOperator::new(n_vertices, faces)?,
        })
    }

    /// The flow on the planar map `x`, with the density diffused over time `tau` before its
    /// gradient is taken (A.10).
    pub fn evaluate(&self, x: &[[f64; 3]], tau: f64) -> Result<FlowState> {
        let (areas, rho_f) = self.face_density(x);
        let rho_v = self.incidence.average(&rho_f);
        let factor = self.diffusion.factor(x, &areas, tau, &[])?;
        let rho = factor.diffuse(&rho_v);
        let grad_f = face_gradient(x, self.faces, &rho);
        // DEQ takes the vertex gradient as the plain mean of the face gradients around the
        // vertex, like the density: with the area weights of (A.14) a triangle crushed against
        // a boundary has no say in the motion of its one free corner, which is what would
        // reopen it (peaks_7: Var(ρ̃) stalls at 24.7 with area weights, reaches 0.73 without).
        // LDEQ keeps (A.14): while its landmarks travel, the plain mean let the variance of the
        // four-quadrant annulus grow to 2.1 (0.18 with the area weights).
        let grad_x: Vec<f64> = grad_f.iter().map(|g| g[0]).collect();
        let grad_y: Vec<f64> = grad_f.iter().map(|g| g[1]).collect();
        let (gx, gy) = if self.area_weighted_gradient {
            let g = self.incidence.apply_vec(&areas, &grad_f);
            (
                g.iter().map(|v| v[0]).collect(),
                g.iter().map(|v| v[1]).collect(),
            )
        } else {
            (
                self.incidence.average(&grad_x),
                self.incidence.average(&grad_y),
            )
        };
        // v = −∇ρ/ρ, smoothed once with the same factor, (A + τL) v̄ = A v (as in DEM's
        // iteration): it removes the triangle-scale noise of the face gradients, which would
        // otherwise limit the step to a fraction of a triangle.
        let mut vx: Vec<f64> = gx.iter().zip(&rho).map(|(g, r)| -g / r).collect();
        let mut vy: Vec<f64> = gy.iter().zip(&rho).map(|(g, r)| -g / r).collect();
        for v in [&mut vx, &mut vy] {
            for (c, m) in v.iter_mut().zip(&factor.mass) {
                *c *= m;
            }
            factor.factor.solve_in_place(v);
        }
        let velocity = vx.into_iter().zip(vy).map(|(a, b)| [a, b]).collect();
        Ok(FlowState { velocity })
    }
}

/// How far a map is from equalizing the density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Fit {
    /// Var(ρ_F / mean ρ_F), the paper's Var(ρ̃).
    pub var: f64,
    /// Mean |log((A/ΣA)/(P/ΣP))| over the faces (the report's `density_error_mean`).
    pub error: f64,
}

impl Fit {
    /// The steps' acceptance test: `next` lowers Var(ρ̃), or it lowers the density error
    /// while raising Var(ρ̃) by at most 10%. The variance is what the method is judged by,
    /// but it is dominated by the few faces of a heavy-tailed density: when no step lowers
    /// it, a step that improves the bulk of the faces still moves the map on (the iteration
    /// keeps the best map met).
    pub fn improved_by(&self, next: &Fit) -> bool {
        next.var < self.var || (next.error < self.error && next.var <= 1.1 * self.var)
    }
}

impl DensityFlow<'_> {
    /// The face areas of the planar map `x` and the face density `ρ_F = P / A`.
    fn face_density(&self, x: &[[f64; 3]]) -> (Vec<f64>, Vec<f64>) {
        let areas = face_areas(x, self.faces);
        let rho_f = self
            .population
            .iter()
            .zip(&areas)
            .map(|(p, a)| p / a.max(f64::MIN_POSITIVE))
            .collect();
        (areas, rho_f)
    }

    /// The [`Fit`] of the planar map `x`.
    pub fn fit(&self, x: &[[f64; 3]]) -> Fit {
        let (areas, rho_f) = self.face_density(x);
        let areas: Vec<f64> = areas.iter().map(|a| a.max(f64::MIN_POSITIVE)).collect();
        Fit {
            var: normalized_variance(&rho_f),
            error: crate::metrics::density_error(self.population, &areas).0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;

    #[test]
    fn circle_projection_and_frame() {
        let c = Circle {
            center: [1.0, -1.0],
            radius: 2.0,
        };
        let p = c.project([4.0, 3.0, 0.7]);
        assert!(
            (p[0] - (1.0 + 2.0 * 0.6)).abs() < 1e-15 && (p[1] - (-1.0 + 2.0 * 0.8)).abs() < 1e-15
        );
        assert_eq!(p[2], 0.0);
        let t = c.tangent([4.0, 3.0, 0.0]);
        assert!((t[0] + 0.8).abs() < 1e-15 && (t[1] - 0.6).abs() < 1e-15);
    }

    #[test]
    fn velocity_points_from_dense_to_sparse() {
        // Density 3 on x > 0, 1 on x < 0: the flow pushes the middle towards −x.
        let m = annulus(0.3, 1.0, 8, 64).unwrap();
        let areas = face_areas(&m.positions, &m.faces);
        let pop: Vec<f64> = m
            .faces
            .iter()
            .zip(&areas)
            .map(|(f, a)| {
                let cx: f64 = f.iter().map(|&v| m.positions[v as usize][0]).sum::<f64>() / 3.0;
                a * if cx > 0.0 { 3.0 } else { 1.0 }
            })
            .collect();
        let flow = DensityFlow::new(m.n_vertices(), &m.faces, &pop).unwrap();
        let s = flow.evaluate(&m.positions, 0.01).unwrap();
        let near_axis: Vec<&[f64; 2]> = m
            .positions
            .iter()
            .zip(&s.velocity)
            .filter(|(p, _)| p[0].abs() < 0.05 && p[1].abs() > 0.4)
            .map(|(_, v)| v)
            .collect();
        assert!(!near_axis.is_empty());
        assert!(near_axis.iter().all(|v| v[0] < 0.0));
        assert!(flow.fit(&m.positions).var > 0.2);
    }
}
