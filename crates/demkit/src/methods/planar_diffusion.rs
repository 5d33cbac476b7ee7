//! The density-equalizing iteration on a planar triangulation (DEM paper Alg. 5 lines 10–17,
//! Alg. 6 lines 5–13), shared by DEM and shape-prescribed DEM, with two additions:
//!
//! - **recoupling** (SDEM paper §3.1.4, (3.22)): every iteration re-derives the face density
//!   `ρ_F = P / A` from the current map before the diffusion step, so the map follows the
//!   density it actually has rather than a diffused field that equalizes long before the map;
//! - **bijectivity**: a step that would flip a triangle is corrected with the Beltrami
//!   shortened locally where a triangle would collapse, as the DEM paper's §7.3 suggests.

use super::{Progress, StopReason};
use crate::Result;
use crate::fem::{VertexFaces, cotangent_weights, face_gradient, lumped_mass};
use crate::geometry::{face_areas, signed_area_2d};
use crate::init::shape::Shape;
use crate::linalg::{CachedCholesky, StiffnessPattern};
use rayon::prelude::*;

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
    /// Boundary vertices projected onto a prescribed shape after every step (Alg. 6 line 12).
    pub shape: Option<(Vec<u32>, Shape)>,
    /// Time step δt (the smallest one when adaptive).
    pub dt: f64,
    /// Recompute δt by (4.39) from the current density every iteration (never below `dt`).
    pub adaptive_dt: bool,
    /// Stop when sd/mean of the recoupled ROI vertex density falls below this.
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Iterations without improvement of the density error before stopping as stationary.
    pub patience: usize,
}

/// The result of the iteration.
pub(crate) struct Outcome {
    /// The best map met (lowest density error), all vertices.
    pub positions: Vec<[f64; 3]>,
    pub iterations: usize,
    pub history: Vec<f64>,
    pub stop_reason: StopReason,
}

struct Measure {
    /// sd/mean of the recoupled vertex density over the ROI (the stop quantity).
    sd_over_mean: f64,
    /// Mean |log(A/P)| (normalized) over the ROI faces.
    error: f64,
}

/// Runs the iteration from the flip-free map `r` (z = 0).
pub(crate) fn run(
    problem: &Problem,
    mut r: Vec<[f64; 3]>,
    progress: &mut dyn FnMut(Progress),
) -> Result<Outcome> {
    let n = r.len();
    let faces = problem.faces;
    let (nv, nf) = (problem.n_roi_vertices, problem.n_roi_faces);
    // ROI vertices average over ROI faces only, sea vertices over sea faces only (DEM §4.3:
    // the density at the ROI boundary must not be blurred by the sea).
    let incidence = VertexFaces::new_filtered(n, faces, |v, f| (v < nv) == (f < nf));
    let incidence_all = VertexFaces::new(n, faces);
    let pattern = StiffnessPattern::new(n, faces, None);
    let cholesky = CachedCholesky::new(&pattern)?;
    let mut values = vec![0.0; pattern.nnz()];

    let measure = |r: &[[f64; 3]]| -> (Measure, Vec<f64>, Vec<f64>) {
        let areas = face_areas(r, faces);
        let rho_f: Vec<f64> = problem
            .population
            .iter()
            .zip(&areas)
            .map(|(p, a)| p / a)
            .collect();
        let rho_v = incidence.apply(&areas, &rho_f);
        // sd of ρ/mean rather than sd(ρ)/mean: squares of tiny densities would underflow.
        let roi = &rho_v[..nv];
        let mean = roi.iter().sum::<f64>() / nv as f64;
        let sd_over_mean =
            (roi.iter().map(|x| (x / mean - 1.0).powi(2)).sum::<f64>() / nv as f64).sqrt();
        let sp: f64 = problem.population[..nf].iter().sum();
        let sa: f64 = areas[..nf].iter().sum();
        let error = problem.population[..nf]
            .iter()
            .zip(&areas[..nf])
            .map(|(p, a)| ((a / sa) / (p / sp)).ln().abs())
            .sum::<f64>()
            / nf as f64;
        (
            Measure {
                sd_over_mean,
                error,
            },
            areas,
            rho_v,
        )
    };

    let (mut m, mut areas, mut rho_v) = measure(&r);
    let mut history = Vec::new();
    let mut best = (m.error, r.clone());
    let mut since_best = 0usize;
    if m.sd_over_mean < problem.epsilon {
        return Ok(Outcome {
            positions: r,
            iterations: 0,
            history,
            stop_reason: StopReason::Tolerance,
        });
    }
    let mut stop_reason = StopReason::MaxIter;
    let mut iterations = 0;
    for it in 1..=problem.max_iter {
        iterations = it;
        // Diffusion step (4.34): (A + δt L) ρ_n = A ρ_{n−1}.
        // δt by (4.39) on the current (recoupled) density: the diffusion restarts every
        // iteration, so its time scale follows the density's current spread.
        let dt = if problem.adaptive_dt {
            let roi_area: f64 = areas[..nf].iter().sum();
            super::disk_input::default_time_step(&rho_v[..nv], roi_area).max(problem.dt)
        } else {
            problem.dt
        };
        let mut w = cotangent_weights(&r, faces);
        for x in w.iter_mut() {
            *x = x.map(|c| c * dt);
        }
        let mass = lumped_mass(n, faces, &areas);
        pattern.assemble(&w, &mass, &mut values);
        let factor = cholesky.factor(&pattern, &values)?;
        let mut rho: Vec<f64> = mass.iter().zip(&rho_v).map(|(a, p)| a * p).collect();
        factor.solve_in_place(&mut rho);
        let floor = rho_v.iter().cloned().fold(f64::INFINITY, f64::min) * 1e-3;
        for x in rho.iter_mut() {
            if !(*x > floor) {
                *x = floor;
            }
        }
        // Gradient (4.37), W^FV (4.31), velocity −∇ρ/ρ (3.4).
        let grad_f = face_gradient(&r, faces, &rho);
        let grad_v = incidence_all.apply_vec(&areas, &grad_f);
        let step: Vec<[f64; 2]> = grad_v
            .iter()
            .zip(&rho)
            .map(|(g, p)| [-dt * g[0] / p, -dt * g[1] / p])
            .collect();
        safe_update(problem, &mut r, &step);

        let (m2, a2, rv2) = measure(&r);
        (m, areas, rho_v) = (m2, a2, rv2);
        history.push(m.sd_over_mean);
        progress(Progress {
            iteration: it,
            max_iter: problem.max_iter,
            error: m.sd_over_mean,
        });
        if m.error < best.0 * (1.0 - 1e-4) {
            best = (m.error, r.clone());
            since_best = 0;
        } else {
            since_best += 1;
        }
        if m.sd_over_mean < problem.epsilon {
            stop_reason = StopReason::Tolerance;
            best.1 = r.clone();
            break;
        }
        if since_best >= problem.patience {
            stop_reason = StopReason::Stationary;
            break;
        }
    }
    Ok(Outcome {
        positions: best.1,
        iterations,
        history,
        stop_reason,
    })
}

fn has_flip(r: &[[f64; 3]], faces: &[[u32; 3]]) -> bool {
    use rayon::prelude::*;
    faces
        .par_iter()
        .any(|f| !(signed_area_2d(r[f[0] as usize], r[f[1] as usize], r[f[2] as usize]) > 0.0))
}

fn project_shape(problem: &Problem, r: &mut [[f64; 3]]) {
    if let Some((boundary, shape)) = &problem.shape {
        for &v in boundary {
            let p = shape.project([r[v as usize][0], r[v as usize][1]]);
            r[v as usize] = [p[0], p[1], 0.0];
        }
    }
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

/// Moves `r` by `step` without flipping any triangle, keeping a margin: the step is scaled
/// uniformly to `τ = min(1, t/2)`, where `t` is the earliest time at which a triangle moving
/// linearly along the step would collapse ([`collapse_time`]); a uniform scaling of a linear
/// motion keeps every triangle positive, and the margin keeps triangles from being squeezed
/// almost flat in one step. With a prescribed shape the boundary vertices are projected back
/// onto it, halving τ while that flips a triangle; if nothing works the map stays put.
fn safe_update(problem: &Problem, r: &mut Vec<[f64; 3]>, step: &[[f64; 2]]) {
    let faces = problem.faces;
    let t_min = faces
        .par_iter()
        .map(|f| collapse_time(f.map(|v| r[v as usize]), f.map(|v| step[v as usize])))
        .reduce(|| f64::INFINITY, f64::min);
    let mut tau = (0.5 * t_min).min(1.0);
    for _ in 0..12 {
        let mut proposal: Vec<[f64; 3]> = r
            .iter()
            .zip(step)
            .map(|(p, s)| [p[0] + tau * s[0], p[1] + tau * s[1], 0.0])
            .collect();
        project_shape(problem, &mut proposal);
        if !has_flip(&proposal, faces) {
            *r = proposal;
            return;
        }
        tau *= 0.5;
    }
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
            shape: None,
            dt: 1.0,
            adaptive_dt: false,
            epsilon: 1e-3,
            max_iter: 1,
            patience: 1,
        };
        let mut r = pos.clone();
        safe_update(&problem, &mut r, &step);
        assert!(!has_flip(&r, &faces));
        assert!(r != pos, "the map must still move");
    }
}
