//! Moving points with the diffusion flow from t = 0 until the density is uniform: Heun's
//! predictor–corrector with an adaptive step. A step is taken only when the corrector agrees
//! with the predictor within [`TOLERANCE`] cells and when it is short enough, against the
//! velocity's spatial derivative, that the step's map of the plane cannot fold a cell
//! (its Jacobian I + δt·∇v stays close to the identity), so the map stays one-to-one.

use super::diffusion::{Diffusion, Velocity};
use rayon::prelude::*;

/// Largest distance, in cells, between predictor and corrector in an accepted step.
pub const TOLERANCE: f64 = 0.02;

/// A step times the velocity's derivative bound stays below this.
const FOLD_MARGIN: f64 = 0.4;

/// How the integration went.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integration {
    /// Accepted steps.
    pub steps: usize,
    /// Densities computed (accepted and refused steps).
    pub evaluations: usize,
    /// Whether the flow reached its end (false: the step limit came first).
    pub finished: bool,
}

/// Moves `points` (cell units, inside the nx × ny grid of `diffusion`) with the flow, at most
/// `max_steps` accepted steps, from time `t_start` (the density blurred by the diffusion up
/// to then) on. The flow ends at t = nx² + ny², when the slowest mode of the
/// density has decayed to e^−π² of its start.
pub fn advect(
    diffusion: &Diffusion,
    nx: usize,
    ny: usize,
    points: &mut [[f64; 2]],
    max_steps: usize,
    t_start: f64,
) -> Integration {
    let t_end = (nx * nx + ny * ny) as f64;
    let mut t = t_start.max(0.0);
    let mut v1 = diffusion.velocity(&diffusion.density(t));
    let mut evaluations = 1;
    let mut dt = FOLD_MARGIN / v1.lipschitz.max(1e-12);
    let mut steps = 0;
    let mut predicted = vec![[0.0; 2]; points.len()];
    let mut corrected = vec![[0.0; 2]; points.len()];
    let mut start: Vec<[f64; 2]> = points.par_iter().map(|&p| v1.at(p)).collect();
    let clamp = |p: [f64; 2]| [p[0].clamp(0.0, nx as f64), p[1].clamp(0.0, ny as f64)];
    while t < t_end && steps < max_steps {
        dt = dt.min(FOLD_MARGIN / v1.lipschitz.max(1e-12)).min(t_end - t);
        predicted
            .par_iter_mut()
            .zip(points.par_iter())
            .zip(start.par_iter())
            .for_each(|((q, p), v)| *q = clamp([p[0] + dt * v[0], p[1] + dt * v[1]]));
        let v2: Velocity = diffusion.velocity(&diffusion.density(t + dt));
        evaluations += 1;
        // The corrector, kept for the step if it is accepted, and its gap to the predictor.
        let err = corrected
            .par_iter_mut()
            .zip(points.par_iter())
            .zip(predicted.par_iter().zip(start.par_iter()))
            .map(|((c, p), (q, a))| {
                let b = v2.at(*q);
                let u = [
                    p[0] + 0.5 * dt * (a[0] + b[0]),
                    p[1] + 0.5 * dt * (a[1] + b[1]),
                ];
                *c = clamp(u);
                (u[0] - q[0]).abs().max((u[1] - q[1]).abs())
            })
            .reduce(|| 0.0, f64::max);
        let folds = dt * v2.lipschitz > FOLD_MARGIN;
        // Heun's predictor–corrector gap grows as the step squared.
        let factor = if err > 0.0 {
            0.9 * (TOLERANCE / err).sqrt()
        } else {
            2.0
        };
        if (err > TOLERANCE || folds) && dt > 1e-9 {
            dt *= if folds { 0.5 } else { factor.clamp(0.2, 0.5) };
            continue;
        }
        points.copy_from_slice(&corrected);
        t += dt;
        steps += 1;
        v1 = v2;
        start
            .par_iter_mut()
            .zip(points.par_iter())
            .for_each(|(s, &p)| *s = v1.at(p));
        dt *= factor.clamp(1.0, 2.0);
    }
    Integration {
        steps,
        evaluations,
        finished: t >= t_end,
    }
}
