//! Moving points with the flow ([`super::flow::Flow`]) from t = 0 to t = 1: Heun's
//! predictor–corrector with an adaptive step. A step is taken only when the corrector agrees
//! with the predictor within [`TOLERANCE`] cells and when it is short enough, against the
//! velocity's spatial derivative around the points, that the step's map cannot fold the
//! neighbourhood of any point (its Jacobian I + δt·∇v stays close to the identity), so the
//! polygons' edges, no longer than a cell, cannot cross.

use super::flow::Flow;
use rayon::prelude::*;

/// Largest distance, in cells, between predictor and corrector in an accepted step.
pub const TOLERANCE: f64 = 0.1;

/// A step times the velocity's derivative bound stays below this.
const FOLD_MARGIN: f64 = 0.4;

/// The shortest step tried before a step is taken whatever its error.
const MIN_STEP: f64 = 1e-9;

/// How the integration went.
#[derive(Debug, Clone, PartialEq)]
pub struct Integration {
    /// Accepted steps.
    pub steps: usize,
    /// Whether the flow reached t = 1 (false: the step limit came first).
    pub finished: bool,
    /// The accepted steps' start times and lengths, for [`replay`].
    pub schedule: Vec<(f64, f64)>,
}

/// One of Heun's steps from `p` at time `t` of length `dt`, clamped into the grid.
fn heun(flow: &Flow, nx: usize, ny: usize, p: [f64; 2], t: f64, dt: f64) -> [f64; 2] {
    let clamp = |p: [f64; 2]| [p[0].clamp(0.0, nx as f64), p[1].clamp(0.0, ny as f64)];
    let a = flow.at(p, t);
    let q = clamp([p[0] + dt * a[0], p[1] + dt * a[1]]);
    let b = flow.at(q, t + dt);
    clamp([
        p[0] + 0.5 * dt * (a[0] + b[0]),
        p[1] + 0.5 * dt * (a[1] + b[1]),
    ])
}

/// Moves `points` with the steps [`advect`] accepted for other points of the same flow
/// (`schedule`): the same map, so points added between those (on their edges) land where the
/// flow takes them relative to the others, at the cost of these points alone.
pub fn replay(flow: &Flow, nx: usize, ny: usize, points: &mut [[f64; 2]], schedule: &[(f64, f64)]) {
    points.par_iter_mut().for_each(|p| {
        for &(t, dt) in schedule {
            *p = heun(flow, nx, ny, *p, t, dt);
        }
    });
}

/// Moves `points` (cell units, inside the nx × ny grid of `flow`) with the flow from t = 0
/// to t = 1, at most `max_steps` accepted steps.
pub fn advect(
    flow: &Flow,
    nx: usize,
    ny: usize,
    points: &mut [[f64; 2]],
    max_steps: usize,
) -> Integration {
    let mut t = 0.0;
    let lipschitz = |pts: &[[f64; 2]], t: f64| {
        pts.par_iter()
            .map(|&p| flow.local_lipschitz(p, t))
            .reduce(|| 0.0, f64::max)
    };
    let mut lip = lipschitz(points, t);
    let mut dt = (FOLD_MARGIN / lip.max(1e-12)).min(1.0);
    let mut steps = 0;
    let mut schedule = Vec::new();
    let mut predicted = vec![[0.0; 2]; points.len()];
    let mut corrected = vec![[0.0; 2]; points.len()];
    let mut start: Vec<[f64; 2]> = points.par_iter().map(|&p| flow.at(p, t)).collect();
    let clamp = |p: [f64; 2]| [p[0].clamp(0.0, nx as f64), p[1].clamp(0.0, ny as f64)];
    while t < 1.0 && steps < max_steps {
        dt = dt.min(FOLD_MARGIN / lip.max(1e-12)).min(1.0 - t);
        predicted
            .par_iter_mut()
            .zip(points.par_iter())
            .zip(start.par_iter())
            .for_each(|((q, p), v)| *q = clamp([p[0] + dt * v[0], p[1] + dt * v[1]]));
        // The corrector, kept for the step if it is accepted, and its gap to the predictor.
        // With the largest derivative bound at the predicted points.
        let (err, lip_next) = corrected
            .par_iter_mut()
            .zip(points.par_iter())
            .zip(predicted.par_iter().zip(start.par_iter()))
            .map(|((c, p), (q, a))| {
                let b = flow.at(*q, t + dt);
                let u = [
                    p[0] + 0.5 * dt * (a[0] + b[0]),
                    p[1] + 0.5 * dt * (a[1] + b[1]),
                ];
                *c = clamp(u);
                let gap = (u[0] - q[0]).abs().max((u[1] - q[1]).abs());
                (gap, flow.local_lipschitz(*q, t + dt))
            })
            .reduce(|| (0.0, 0.0), |x, y| (x.0.max(y.0), x.1.max(y.1)));
        if dt * lip_next > FOLD_MARGIN && dt > MIN_STEP {
            dt *= 0.5;
            continue;
        }
        // Heun's predictor–corrector gap grows as the step squared.
        let factor = if err > 0.0 {
            0.9 * (TOLERANCE / err).sqrt()
        } else {
            2.0
        };
        if err > TOLERANCE && dt > MIN_STEP {
            dt *= factor.clamp(0.2, 0.5);
            continue;
        }
        points.copy_from_slice(&corrected);
        schedule.push((t, dt));
        t += dt;
        steps += 1;
        lip = lip_next;
        start
            .par_iter_mut()
            .zip(points.par_iter())
            .for_each(|(s, &p)| *s = flow.at(p, t));
        dt *= factor.clamp(1.0, 2.0);
    }
    Integration {
        steps,
        finished: t >= 1.0,
        schedule,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of n × n cells, the middle block of side n/4 `contrast` times as dense as the
    /// rest; its boundary after the flow, with `blur`.
    fn block(n: usize, contrast: f64, blur: f64) -> (f64, f64) {
        let (lo, hi) = (3 * n / 8, 5 * n / 8);
        let rho: Vec<f64> = (0..n * n)
            .map(|c| {
                let (x, y) = (c % n, c / n);
                if (lo..hi).contains(&x) && (lo..hi).contains(&y) {
                    contrast
                } else {
                    1.0
                }
            })
            .collect();
        let flow = Flow::new(&rho, n, n, blur);
        let (a, s) = (lo as f64, (hi - lo) as f64);
        let mut pts = Vec::new();
        for side in 0..4 {
            for k in 0..64 {
                let f = s * k as f64 / 64.0;
                pts.push(match side {
                    0 => [a + f, a],
                    1 => [a + s, a + f],
                    2 => [a + s - f, a + s],
                    _ => [a, a + s - f],
                });
            }
        }
        let start = pts.clone();
        let run = advect(&flow, n, n, &mut pts, 10_000);
        assert!(run.finished && run.steps > 1);
        // The same steps replayed give the same map.
        let mut again = start;
        replay(&flow, n, n, &mut again, &run.schedule);
        assert_eq!(again, pts);
        let area = super::super::regions::ring_area(&pts).abs();
        let mass = contrast * s * s;
        let want = mass / (mass + (n * n) as f64 - s * s) * (n * n) as f64;
        (area, want)
    }

    #[test]
    fn a_dense_square_grows_to_its_share_and_the_error_falls_with_the_cell() {
        // Unblurred, the error is of the order of a cell on the block's side.
        let rel = |n: usize| {
            let (area, want) = block(n, 4.0, 0.0);
            (area - want).abs() / want
        };
        let (coarse, fine) = (rel(32), rel(128));
        assert!(fine < 0.015, "{fine}");
        assert!(fine < 0.5 * coarse, "{fine} vs {coarse}");
    }
}
