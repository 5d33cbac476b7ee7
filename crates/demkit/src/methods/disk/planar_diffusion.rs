//! The density-equalizing iteration on a planar triangulation (DEM paper Alg. 5 lines 10–17,
//! Alg. 6 lines 5–13), shared by DEM and shape-prescribed DEM, with two additions:
//!
//! - **recoupling** (SDEM paper §3.1.4, (3.22)): every iteration re-derives the face density
//!   `ρ_F = P / A` from the current map before the diffusion step, so the map follows the
//!   density it actually has rather than a diffused field that equalizes long before the map;
//! - **bijectivity**: a step that would squeeze a triangle more than halfway to collapse is
//!   shortened uniformly ([`safe_update`]), which never flips a triangle (§7.3 asks for
//!   exactly such a safeguard).

use crate::Result;
use crate::fem::{DiffusionOperator, REFACTOR_DRIFT, VertexFaces, face_gradient_into};
use crate::geometry::face_areas;
use crate::methods::iteration::{
    Flow, Keep, Measured, Moved, Rules, Stationary, Step, diffusion_time_step, iterate,
};
use crate::methods::{Progress, StopReason};
use crate::metrics::log_area_misfit;
use crate::metrics::normalized_variance;
use crate::shape::Shape;
use rayon::prelude::*;
use std::cell::RefCell;

/// How the vertices of a planar diffusion problem may move.
pub(crate) trait Constraint {
    /// Replaces the displacement `step` (per vertex) of the map `r` by the part of it the
    /// constraint admits, in place. Default: every vertex moves freely.
    fn admissible_step(&self, _r: &[[f64; 3]], _step: &mut [[f64; 2]]) {}

    /// The map after moving `r` by `tau · step`, `step` admissible.
    fn realize(&self, r: &[[f64; 3]], step: &[[f64; 2]], tau: f64) -> Vec<[f64; 3]> {
        linear_move(r, step, tau)
    }

    /// True when the collapse of `face` limits a step (default: every face).
    fn limits_step(&self, _face: usize) -> bool {
        true
    }

    /// Improves the map after a density move over diffusion time `time` without folding it
    /// (default: nothing).
    fn regularize(&self, _r: &mut [[f64; 3]], _time: f64) {}
}

/// `r + tau · step` (z = 0).
pub(crate) fn linear_move(r: &[[f64; 3]], step: &[[f64; 2]], tau: f64) -> Vec<[f64; 3]> {
    r.iter()
        .zip(step)
        .map(|(p, s)| [p[0] + tau * s[0], p[1] + tau * s[1], 0.0])
        .collect()
}

/// Every vertex moves freely (DEM with its sea).
pub(crate) struct Free;

impl Constraint for Free {}

/// The boundary `loop_` slides along a prescribed shape (Alg. 6 line 12): boundary vertices are
/// projected back onto it after every move.
pub(crate) struct OnShape {
    pub boundary: Vec<u32>,
    pub shape: Shape,
}

impl Constraint for OnShape {
    fn realize(&self, r: &[[f64; 3]], step: &[[f64; 2]], tau: f64) -> Vec<[f64; 3]> {
        let mut out = linear_move(r, step, tau);
        for &v in &self.boundary {
            let p = self.shape.project([out[v as usize][0], out[v as usize][1]]);
            out[v as usize] = [p[0], p[1], 0.0];
        }
        out
    }
}

/// A planar diffusion problem: an (extended) triangulation whose first `n_roi_faces` faces and
/// `n_roi_vertices` vertices are the region of interest, the rest a sea (possibly empty).
pub(crate) struct Problem<'a> {
    /// Faces of the whole triangulation (counter-clockwise).
    pub faces: &'a [[u32; 3]],
    /// Population of every face (sea faces: the mean density times their initial area).
    pub population: Vec<f64>,
    /// Number of region-of-interest vertices (they come first).
    pub n_roi_vertices: usize,
    /// Number of region-of-interest faces (they come first).
    pub n_roi_faces: usize,
    /// How the vertices may move (free, a boundary on a shape, a circle domain).
    pub constraint: &'a dyn Constraint,
    /// A fixed time step δt; `None` recomputes δt by (4.39) from the current density.
    pub dt: Option<f64>,
    /// Stop when sd/mean of the recoupled ROI vertex density falls below this.
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Stop as stationary when the best density error has improved by less than
    /// [`STATIONARY_GAIN`] over this many iterations.
    pub patience: usize,
}

/// The longest diffusion time, as a fraction of the ROI's area (see [`run`]): a diffusion
/// length of 5% of the domain's size. The flow starts with this bound and makes it finer by
/// [`SMOOTHING_RATIO`] whenever it stops making progress at it.
const SMOOTHING_AREA: f64 = 1.0 / 400.0;

/// The finest bound on the diffusion time, in mean ROI face areas: about two rings of
/// triangles. (A single bound of 30 faces, the rule before the coarse-to-fine schedule, took the
/// 106 000-face hand 104 iterations to 0.055; the schedule ending at 10 faces takes 36 to
/// 0.049 and leaves every other surface tried at least as accurate as before.)
const SMOOTHING_FACES: f64 = 10.0;

/// Each refinement of the diffusion time's bound divides it by this.
const SMOOTHING_RATIO: f64 = 4.0;

/// The relative improvement of the best density error over `patience` iterations below which
/// the map counts as stationary.
const STATIONARY_GAIN: f64 = 0.02;

/// The result of the iteration.
pub(crate) struct Outcome {
    /// The best map met (lowest density error), all vertices.
    pub positions: Vec<[f64; 3]>,
    pub iterations: usize,
    pub history: Vec<f64>,
    pub stop_reason: StopReason,
}

/// The recoupled density of a planar map, as the flow measures it.
pub(crate) struct Density {
    /// Current face areas (all faces).
    areas: Vec<f64>,
    /// Recoupled vertex density (4.27) of the current map (all vertices).
    rho_v: Vec<f64>,
    /// Total area of the ROI faces.
    roi_area: f64,
    /// The direction the flow last computed from this map, reused by a retry or a longer move
    /// from it (`Step::Search`).
    direction: RefCell<Option<Direction>>,
}

/// An admissible velocity per unit step, with the smoothing level it was computed at and the
/// earliest collapse time of a limiting face under it (the collapse time of a step `h v` is
/// that of `v` divided by `h`).
struct Direction {
    level: u32,
    velocity: Vec<[f64; 2]>,
    collapse: f64,
}

/// The planar density-equalizing flow of a [`Problem`] (see [`run`]).
struct PlanarFlow<'p, 'a> {
    problem: &'p Problem<'a>,
    /// ROI vertices average over ROI faces only, sea vertices over sea faces only.
    incidence: VertexFaces,
    incidence_all: VertexFaces,
    diffusion: DiffusionOperator,
    grad_f: Vec<[f64; 3]>,
    /// How often the bound on the diffusion time has been refined ([`Flow::refine`]).
    level: u32,
}

impl Flow for PlanarFlow<'_, '_> {
    type Map = Vec<[f64; 3]>;
    type Data = Density;

    /// The stopping quantity is sd/mean of the recoupled ROI vertex density; maps are compared
    /// by the mean |log((A/ΣA)/(P/ΣP))| over the ROI faces.
    fn measure(&mut self, r: &Vec<[f64; 3]>) -> Result<Measured<Density>> {
        let p = self.problem;
        let (nv, nf) = (p.n_roi_vertices, p.n_roi_faces);
        let areas = face_areas(r, p.faces);
        let rho_f: Vec<f64> = p
            .population
            .iter()
            .zip(&areas)
            .map(|(p, a)| p / a)
            .collect();
        let rho_v = self.incidence.average(&rho_f);
        let sd_over_mean = normalized_variance(&rho_v[..nv]).sqrt();
        let roi_area: f64 = areas[..nf].iter().sum();
        let merit = log_area_misfit(&p.population[..nf], &areas[..nf]);
        Ok(Measured {
            error: sd_over_mean,
            merit,
            data: Density {
                areas,
                rho_v,
                roi_area,
                direction: RefCell::new(None),
            },
        })
    }

    /// δt of (4.39) for the current ROI density.
    fn step_cap(&self, m: &Measured<Density>) -> f64 {
        let nv = self.problem.n_roi_vertices;
        diffusion_time_step(&m.data.rho_v[..nv], m.data.roi_area)
    }

    /// The bound on the diffusion time is made finer by [`SMOOTHING_RATIO`], down to
    /// [`SMOOTHING_FACES`] mean face areas; the step shrinks with it.
    fn refine(&mut self) -> Option<f64> {
        let nf = self.problem.n_roi_faces;
        (smoothing_bound(self.level, nf) > smoothing_bound(self.level + 1, nf)).then(|| {
            self.level += 1;
            1.0 / SMOOTHING_RATIO
        })
    }

    fn advance(
        &mut self,
        r: &Vec<[f64; 3]>,
        m: &Measured<Density>,
        dt: f64,
    ) -> Result<Moved<Vec<[f64; 3]>>> {
        let problem = self.problem;
        let mut direction = m.data.direction.borrow_mut();
        if direction.as_ref().is_none_or(|d| d.level != self.level) {
            *direction = Some(self.direction(r, m, dt)?);
        }
        let Direction {
            velocity, collapse, ..
        } = direction.as_ref().expect("computed above");
        let step: Vec<[f64; 2]> = velocity.iter().map(|v| [dt * v[0], dt * v[1]]).collect();
        let mut moved = r.clone();
        let tau = safe_update(problem, &mut moved, &step, collapse / dt);
        problem.constraint.regularize(&mut moved, tau * dt);
        Ok(Moved {
            map: moved,
            fraction: tau,
        })
    }
}

/// The bound on the diffusion time at refinement `level`, as a fraction of the ROI's area:
/// [`SMOOTHING_AREA`] / [`SMOOTHING_RATIO`]^level, but not below [`SMOOTHING_FACES`] mean
/// face areas (on a coarse mesh, where that is more than [`SMOOTHING_AREA`], the bound stays
/// at [`SMOOTHING_AREA`]).
fn smoothing_bound(level: u32, n_roi_faces: usize) -> f64 {
    (SMOOTHING_AREA / SMOOTHING_RATIO.powi(level as i32))
        .max(SMOOTHING_FACES / n_roi_faces as f64)
        .min(SMOOTHING_AREA)
}

impl PlanarFlow<'_, '_> {
    /// The admissible velocity of the map `r` (measured as `m`) per unit step, for a step of
    /// length `dt` (steps 2–3 of [`run`]).
    fn direction(&mut self, r: &[[f64; 3]], m: &Measured<Density>, dt: f64) -> Result<Direction> {
        let problem = self.problem;
        let n = r.len();
        let Density {
            areas,
            rho_v,
            roi_area,
            ..
        } = &m.data;
        let smoothing_time = dt.min(smoothing_bound(self.level, problem.n_roi_faces) * roi_area);

        // Diffusion (4.34): (A + T L) ρ̃ = A ρ.
        let mut step_operator =
            self.diffusion
                .factor_lazily(r, areas, smoothing_time, REFACTOR_DRIFT)?;
        let rho = step_operator.diffuse(rho_v)?;
        let mass = &step_operator.mass;

        // Velocity −∇ρ̃/ρ̃ by (4.37) and W^FV (3.4), smoothed with the same factor.
        face_gradient_into(r, problem.faces, &rho, &mut self.grad_f);
        let grad_v = self.incidence_all.apply_vec(areas, &self.grad_f);
        let mut velocity = vec![0.0; 2 * n];
        for (i, (g, p)) in grad_v.iter().zip(&rho).enumerate() {
            velocity[i] = -mass[i] * g[0] / p;
            velocity[n + i] = -mass[i] * g[1] / p;
        }
        step_operator.solve_many_in_place(&mut velocity, 2)?;
        let mut velocity: Vec<[f64; 2]> = (0..n).map(|i| [velocity[i], velocity[n + i]]).collect();
        problem.constraint.admissible_step(r, &mut velocity);
        let collapse = earliest_collapse(problem, r, &velocity);
        Ok(Direction {
            level: self.level,
            velocity,
            collapse,
        })
    }
}

/// Runs the iteration from the flip-free map `r` (z = 0) on the shared skeleton
/// ([`iterate`]).
///
/// Each iteration is one step of Alg. 5 lines 11–16 on the recoupled density:
/// 1. `ρ_F = P / A` on the current map, interpolated at the vertices by (4.27) — every face
///    counts equally, so a triangle squeezed too small keeps its say in its vertices' density
///    (with the area weights of (4.29) it would lose it exactly when it matters);
/// 2. the diffusion (4.34) `(A + T L) ρ̃ = A ρ` over `T = min(h, B)` (h the step below):
///    one backward-Euler step of a concentrated density is logarithmically singular (its
///    Green's function is K₀), so the paper's single step over the whole δt gives a velocity
///    that varies wildly across the tiny triangles of a squeezed region. The bound `B` starts
///    at [`SMOOTHING_AREA`] of the ROI's area and is divided by [`SMOOTHING_RATIO`] whenever the
///    flow stops making progress at it, down to [`SMOOTHING_FACES`] mean face areas
///    ([`Flow::refine`]): coarse-to-fine, so the number of iterations does not grow with the
///    mesh's resolution and the finest bound still equalizes the density ring by ring;
/// 3. the velocity `v = −∇ρ̃ / ρ̃` by (4.37) and W^FV, smoothed once with the same factor,
///    `(A + T L) v̄ = A v`, which removes the triangle-scale noise of the face gradients;
/// 4. the move `r ← r + h v̄`, shortened where it would squeeze a triangle more than halfway
///    to collapse ([`safe_update`]).
///
/// Steps 1–3 are computed once per accepted map; a retry after a rejected move and a longer
/// move along an accepted one reuse that direction, scaled (`Step::Search`).
///
/// The step `h`: with a fixed `dt`, `h = dt`. Otherwise adaptive with a search along each
/// direction (`Step::Search`), capped by δt of (4.39) for the current density, and judged on
/// the density error (the mean |log| area misfit). The iteration stops at sd/mean < ε
/// (tolerance) or when the best error has improved by less than [`STATIONARY_GAIN`] over the
/// last `patience` iterations at the finest bound (stationary).
pub(crate) fn run(
    problem: &Problem,
    r: Vec<[f64; 3]>,
    progress: &mut dyn FnMut(Progress),
) -> Result<Outcome> {
    let n = r.len();
    let faces = problem.faces;
    let (nv, nf) = (problem.n_roi_vertices, problem.n_roi_faces);
    // ROI vertices average over ROI faces only, sea vertices over sea faces only (DEM §4.3:
    // the density at the ROI boundary must not be blurred by the sea).
    let mut flow = PlanarFlow {
        problem,
        incidence: VertexFaces::new_filtered(n, faces, |v, f| (v < nv) == (f < nf)),
        incidence_all: VertexFaces::new(n, faces),
        diffusion: DiffusionOperator::new(n, faces)?,
        grad_f: Vec::new(),
        level: 0,
    };
    let rules = Rules {
        epsilon: problem.epsilon,
        max_iter: problem.max_iter,
        step: problem.dt.map_or(Step::Search, Step::Fixed),
        stationary: Some(Stationary::Best {
            window: problem.patience,
            min_gain: STATIONARY_GAIN,
        }),
        keep: Keep::Best,
    };
    let out = iterate(&mut flow, r, &rules, progress)?;
    Ok(Outcome {
        positions: out.map,
        iterations: out.iterations,
        history: out.history,
        stop_reason: out.stop_reason,
    })
}

fn has_flip(r: &[[f64; 3]], faces: &[[u32; 3]]) -> bool {
    use rayon::prelude::*;
    faces
        .par_iter()
        .any(|&f| crate::geometry::planar_flipped(r, f))
}

/// The first time `t > 0` at which the triangle `p + t s` (corners moving linearly) has zero
/// signed area, or +∞. The signed area is the quadratic `a + b t + c t²` with `a > 0`.
pub(crate) fn collapse_time(p: [[f64; 3]; 3], s: [[f64; 2]; 3]) -> f64 {
    let cr = |u: [f64; 2], v: [f64; 2]| u[0] * v[1] - u[1] * v[0];
    let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1]];
    let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1]];
    let d1 = [s[1][0] - s[0][0], s[1][1] - s[0][1]];
    let d2 = [s[2][0] - s[0][0], s[2][1] - s[0][1]];
    let a = cr(e1, e2);
    let b = cr(e1, d2) + cr(d1, e2);
    let c = cr(d1, d2);
    if !(a > 0.0) {
        return 0.0;
    }
    let scale = a.abs() + b.abs() + c.abs();
    if c.abs() <= 1e-12 * scale {
        return if b < 0.0 { -a / b } else { f64::INFINITY };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    let sq = disc.sqrt();
    // Numerically stable roots of c t² + b t + a.
    let q = -0.5 * (b + b.signum() * sq);
    let (t1, t2) = (q / c, if q != 0.0 { a / q } else { f64::INFINITY });
    [t1, t2]
        .into_iter()
        .filter(|&t| t > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// The earliest time at which a face the constraint lets limit the step collapses when every
/// vertex moves linearly along `step` ([`collapse_time`]).
fn earliest_collapse(problem: &Problem, r: &[[f64; 3]], step: &[[f64; 2]]) -> f64 {
    let times: Vec<f64> = problem
        .faces
        .par_iter()
        .map(|f| collapse_time(f.map(|v| r[v as usize]), f.map(|v| step[v as usize])))
        .collect();
    times
        .iter()
        .enumerate()
        .filter(|&(k, _)| problem.constraint.limits_step(k))
        .fold(f64::INFINITY, |m, (_, &t)| m.min(t))
}

/// Moves `r` by `step` without flipping any triangle, keeping a margin: the step is scaled
/// uniformly to `τ = min(1, t/2)`, where `t` is the earliest time at which a triangle moving
/// linearly along the step would collapse (`collapse`, [`earliest_collapse`] of the step;
/// only the faces the constraint lets limit the step); a uniform scaling of a linear motion
/// keeps every triangle positive, and the margin keeps triangles from being squeezed almost
/// flat in one step. The constraint then realizes the move (e.g. projects a boundary back onto
/// its shape), halving τ while that flips a triangle; if nothing works the map stays put.
/// Returns the factor τ applied to the step (0 if the map stayed put).
fn safe_update(problem: &Problem, r: &mut Vec<[f64; 3]>, step: &[[f64; 2]], collapse: f64) -> f64 {
    let faces = problem.faces;
    let constraint = problem.constraint;
    let mut tau = (0.5 * collapse).min(1.0);
    for _ in 0..12 {
        let proposal = constraint.realize(r, step, tau);
        if !has_flip(&proposal, faces) {
            *r = proposal;
            return tau;
        }
        tau *= 0.5;
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collapse_time_of_a_vertex_moving_through_the_opposite_edge() {
        // Apex (0,1) moving straight down by 2 per unit time crosses the base at t = 0.5.
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let s = [[0.0, 0.0], [0.0, 0.0], [0.0, -2.0]];
        assert!((collapse_time(p, s) - 0.5).abs() < 1e-15);
        // Moving up never collapses; a rigid translation never collapses.
        assert_eq!(
            collapse_time(p, [[0.0, 0.0], [0.0, 0.0], [0.0, 2.0]]),
            f64::INFINITY
        );
        assert_eq!(collapse_time(p, [[1.0, 2.0]; 3]), f64::INFINITY);
    }

    #[test]
    fn uniformly_scaled_step_never_flips() {
        let (pos, faces, _) = crate::generate_fixtures::grid(6, 0.2);
        // A wild step field: every vertex jumps far in a pseudo-random direction.
        let step: Vec<[f64; 2]> = (0..pos.len())
            .map(|i| {
                let a = (i as f64 * 2.399).sin() * 3.0;
                [0.4 * a.cos(), 0.4 * a.sin()]
            })
            .collect();
        let full: Vec<[f64; 3]> = pos
            .iter()
            .zip(&step)
            .map(|(p, s)| [p[0] + s[0], p[1] + s[1], 0.0])
            .collect();
        assert!(
            has_flip(&full, &faces),
            "the test step must be one that flips"
        );
        let problem = Problem {
            faces: &faces,
            population: vec![1.0; faces.len()],
            n_roi_vertices: pos.len(),
            n_roi_faces: faces.len(),
            constraint: &Free,
            dt: Some(1.0),
            epsilon: 1e-3,
            max_iter: 1,
            patience: 1,
        };
        let mut r = pos.clone();
        let collapse = earliest_collapse(&problem, &r, &step);
        safe_update(&problem, &mut r, &step, collapse);
        assert!(!has_flip(&r, &faces));
        assert!(r != pos, "the map must still move");
    }
}
