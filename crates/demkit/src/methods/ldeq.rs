//! LDEQ: landmark-matching DEQ (Lyu, Choi & Lui, Algorithm 5.4).
//!
//! As DEQ, with interior landmarks p_i sent to planar targets q_i. Every reconstruction is an
//! LBS with the landmark vertices fixed as well as the boundary, and the Beltrami descent
//! uses the penalty splitting (5.50)–(5.55):
//! 1. `μ ← μ + δt (dμ¹ − 2η(μ − ν))` (5.51)–(5.53), where `δt dμ¹` is the change of the
//!    Beltrami coefficient made by the density move (as in BDED);
//! 2. `g* = LBS(μ)` with the landmark constraints, `μ ← μ(g*)`;
//! 3. `ν` from `(α I − β Δ + η I) ν = η μ` (5.55), solved on the vertices of D⁰;
//! 4. `g = LBS(ν)` with the landmark constraints, and `ν ← ν + δt (μ(g) − ν)`.
//!
//! The explicit penalty step `2 δt η` is 2 with the paper's values (δt = 0.1, η = 10), which
//! would overshoot ν; it is capped at 1 (μ moves at most all the way to ν).
//!
//! The landmarks start where the initial conformal map puts them and travel to their targets
//! with the step: a step of length h moves them by the fraction 2h/δt of what remains (all of
//! it once that is under a hundredth of the domain), and is halved, like every step, while the
//! reconstruction flips a triangle or raises Var(ρ̃) by more than half. So a target far from
//! the landmark's conformal image is reached in several bijective steps instead of one jump.

use super::beltrami_descent::{Relaxation, slide_boundary};
use super::deq::{self, Deq, circle_input};
use super::{MapResult, Progress, ProgressFn, StopReason};
use crate::geometry::count_nonpositive;
use crate::linalg::solve_dense;
use crate::qc::{beltrami_coefficient, cut_off};
use crate::{Error, Result, TriMesh};
use num_complex::Complex64;
use std::time::Instant;

/// LDEQ parameters; `Default` gives the paper's values (§6.2).
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The DEQ parameters (α, β, δt, ε, iteration limit, geometry modification).
    pub deq: deq::Config,
    /// The penalty η of the splitting (5.50) (paper: 10).
    pub eta: f64,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            deq: deq::Config::default(),
            eta: 10.0,
        }
    }
}

/// How many times a step is halved before giving up on it.
const MAX_HALVINGS: usize = 10;

/// Checks the landmarks: interior vertices, distinct, with planar targets inside the unit disk.
fn check_landmarks(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    landmarks: &[(usize, [f64; 3])],
) -> Result<()> {
    super::check_landmark_vertices(landmarks, mesh.n_vertices(), "ldeq")?;
    let mut on_boundary = vec![false; mesh.n_vertices()];
    for &v in loops.iter().flatten() {
        on_boundary[v as usize] = true;
    }
    for (i, &(v, q)) in landmarks.iter().enumerate() {
        let i = i + 1;
        if on_boundary[v] {
            return Err(Error::Landmarks(format!(
                "landmark {i}: vertex {v} is on the boundary; ldeq landmarks must be interior vertices"
            )));
        }
        if !(q[0].hypot(q[1]) < 1.0) || q[2] != 0.0 {
            return Err(Error::Landmarks(format!(
                "landmark {i}: the target ({}, {}, {}) of vertex {v} must be a point of the plane inside the unit disk",
                q[0], q[1], q[2]
            )));
        }
    }
    Ok(())
}

/// Computes the LDEQ map of `mesh` (a connected open genus-0 surface) with one `population`
/// value per face and `landmarks` (vertex, planar target). The result lies in the unit disk.
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    landmarks: &[(usize, [f64; 3])],
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    deq::check_config(&config.deq)?;
    if !(config.eta > 0.0 && config.eta.is_finite()) {
        return Err(Error::Argument(format!(
            "--eta must be positive, got {}",
            config.eta
        )));
    }
    let loops = circle_input(mesh, population, "ldeq")?;
    check_landmarks(mesh, &loops, landmarks)?;
    let t0 = Instant::now();
    let domain = deq::initial_circle_domain(mesh, &loops, population)?;
    let time_init = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let vertices: Vec<usize> = landmarks.iter().map(|l| l.0).collect();
    let mut state = Deq::new(mesh, population, &domain, &config.deq, &vertices)?;
    state.flow.area_weighted_gradient = true;
    let targets: Vec<[f64; 2]> = landmarks.iter().map(|l| [l.1[0], l.1[1]]).collect();
    let outcome = iterate(&state, &vertices, &targets, config, progress)?;
    Ok(MapResult {
        flat_torus: None,
        method: "ldeq",
        positions: outcome.positions,
        initial: domain.positions,
        converged: outcome.stop_reason != StopReason::MaxIter,
        stop_reason: outcome.stop_reason,
        iterations: outcome.iterations,
        history: outcome.history,
        time_init,
        time_map: t1.elapsed().as_secs_f64(),
        notes: outcome.notes,
    })
}

/// Algorithm 5.4 from D⁰ (the state's source), with the landmark `vertices` travelling to
/// `targets`.
fn iterate(
    deq: &Deq,
    vertices: &[usize],
    targets: &[[f64; 2]],
    config: &Config,
    progress: ProgressFn,
) -> Result<deq::Outcome> {
    let c = &config.deq;
    let (alpha, beta, eta, dt) = (c.alpha, c.beta, config.eta, c.dt);
    let relax = Relaxation::new(&deq.source_weights, &deq.incidence, deq.faces);
    let terms = super::geometry_modification::HoleTerms::new(
        deq.faces,
        &deq.source,
        &deq.source_areas,
        &deq.source_weights,
        &deq.incidence,
        &deq.boundary,
        alpha,
        beta,
    );
    let mut boundary = deq.boundary.clone();
    let mut x = deq.source.clone();
    let mut fit = deq.flow.fit(&x);
    let mut energy = deq.energy(&x, fit.var);
    let zero = Complex64::new(0.0, 0.0);
    let mut nu = vec![zero; deq.faces.len()];
    let mut history = Vec::new();
    let mut notes = Vec::new();
    let mut stop_reason = StopReason::MaxIter;
    let mut iterations = 0;
    let mut h = dt;
    let reached = |x: &[[f64; 3]]| {
        vertices
            .iter()
            .zip(targets)
            .all(|(&v, q)| x[v][0] == q[0] && x[v][1] == q[1])
    };
    for it in 1..=c.max_iter {
        iterations = it;
        if c.geometry_update && boundary.loops.len() > 1 {
            let s = deq.flow.evaluate(&x, deq.diffusion_time(&x))?;
            let mu = beltrami_coefficient(&deq.source, &x, deq.faces);
            let rates = terms.rates(&x, &mu, &s.velocity, &boundary);
            if let Some(f) =
                deq.modify_geometry(&mut x, &mut boundary, &rates, &mu, &relax, h, fit)?
            {
                fit = f;
            }
        }
        let s = deq.flow.evaluate(&x, deq.diffusion_time(&x))?;
        let mu_x = beltrami_coefficient(&deq.source, &x, deq.faces);
        let arrived = reached(&x);
        let mut accepted = None;
        let mut step = h;
        for _ in 0..MAX_HALVINGS {
            // The landmarks cover twice the step's share of what remains, and the rest at once
            // when that is within a hundredth of the domain: they arrive in a few steps even
            // when the steps stay short.
            let remaining = vertices
                .iter()
                .zip(targets)
                .map(|(&v, q)| (x[v][0] - q[0]).hypot(x[v][1] - q[1]))
                .fold(0.0, f64::max);
            let mut travel = (2.0 * step / dt).min(1.0);
            if remaining * (1.0 - travel) < 0.01 {
                travel = 1.0;
            }
            let mut y: Vec<[f64; 3]> = x
                .iter()
                .zip(&s.velocity)
                .map(|(p, v)| [p[0] + step * v[0], p[1] + step * v[1], 0.0])
                .collect();
            for lp in &boundary.loops {
                for &v in lp {
                    y[v as usize] = x[v as usize];
                }
            }
            slide_boundary(&mut y, &s.velocity, step, &boundary);
            // The landmarks' next positions, reached by a smooth correction of the move.
            let wanted: Vec<[f64; 2]> = vertices
                .iter()
                .zip(targets)
                .map(|(&v, q)| {
                    let p = x[v];
                    if travel >= 1.0 {
                        *q
                    } else {
                        [p[0] + travel * (q[0] - p[0]), p[1] + travel * (q[1] - p[1])]
                    }
                })
                .collect();
            landmark_correction(&mut y, &x, vertices, &wanted, &boundary);
            // (5.51)–(5.53): the density move, then the penalty pull towards ν.
            let predicted = beltrami_coefficient(&deq.source, &y, deq.faces);
            let pull = (2.0 * step * eta).min(1.0);
            let mu: Vec<Complex64> = predicted
                .iter()
                .zip(&mu_x)
                .zip(&nu)
                .map(|((p, m), n)| {
                    cut_off(
                        if p.is_finite() {
                            p - (m - n) * pull
                        } else {
                            *p
                        },
                        0.1,
                    )
                })
                .collect();
            let g_star = deq.lbs.solve(&deq.source, &mu, &y)?;
            let mu_star: Vec<Complex64> = beltrami_coefficient(&deq.source, &g_star, deq.faces)
                .into_iter()
                .map(|z| cut_off(z, 0.1))
                .collect();
            // (5.55), then the reconstruction with the landmark constraints.
            // A shortened step relaxes proportionally less, so that the step tends to g* as it
            // shrinks (LBS reproduces g* from μ(g*) exactly).
            let f = (step / dt).min(1.0);
            let nu_new = relax.apply(
                &mu_star,
                &mu_star,
                f * alpha / (alpha + eta),
                f * beta / (alpha + eta),
            );
            let g = deq.lbs.solve(&deq.source, &nu_new, &y)?;
            if count_nonpositive(&g, deq.faces) == 0 {
                let f = deq.flow.fit(&g);
                // On the way the variance may grow a little (the landmarks pull against the
                // density), never by more than half at a step.
                if f.var < fit.var || (!arrived && f.var <= 1.5 * fit.var) {
                    let mu_g = beltrami_coefficient(&deq.source, &g, deq.faces);
                    nu = nu_new
                        .iter()
                        .zip(&mu_g)
                        .map(|(n, m)| cut_off(n + (m - n) * (step / dt).min(1.0), 0.1))
                        .collect();
                    accepted = Some((g, f));
                    break;
                }
            }
            step *= 0.5;
        }
        let Some((g, f)) = accepted else {
            stop_reason = StopReason::Stationary;
            break;
        };
        x = g;
        fit = f;
        let e = deq.energy(&x, fit.var);
        history.push(e);
        progress(Progress {
            iteration: it,
            max_iter: c.max_iter,
            error: fit.var,
        });
        if reached(&x) && arrived && (e - energy).abs() < c.epsilon {
            stop_reason = StopReason::Tolerance;
            break;
        }
        energy = e;
        h = (2.0 * step).min(dt);
    }
    if !reached(&x) {
        notes.push(
            "the landmarks did not reach their targets: every step towards them flipped a triangle"
                .into(),
        );
        if stop_reason != StopReason::MaxIter {
            stop_reason = StopReason::Stationary;
        }
    }
    Ok(deq::Outcome {
        positions: x,
        iterations,
        history,
        stop_reason,
        notes,
    })
}

/// Moves the interior vertices of `y` by a smooth field that puts every landmark exactly at
/// `wanted`: Gaussian radial basis functions `exp(−|z − z_i|²/σ²)` centred at the landmarks'
/// positions in `x`, with σ half the distance from the landmarks to the nearest boundary
/// circle, solved so that the field takes the missing displacement at every landmark. A point
/// constraint alone (only the landmark vertex moved) would concentrate the whole displacement
/// in its ring of triangles.
fn landmark_correction(
    y: &mut [[f64; 3]],
    x: &[[f64; 3]],
    vertices: &[usize],
    wanted: &[[f64; 2]],
    boundary: &super::circle_flow::CircleBoundary,
) {
    let m = vertices.len();
    let centres: Vec<[f64; 2]> = vertices.iter().map(|&v| [x[v][0], x[v][1]]).collect();
    let clearance = centres
        .iter()
        .map(|c| {
            boundary
                .circles
                .iter()
                .enumerate()
                .map(|(l, k)| {
                    let d = (c[0] - k.center[0]).hypot(c[1] - k.center[1]);
                    if l == 0 { k.radius - d } else { d - k.radius }
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min);
    let sigma2 = (0.5 * clearance.max(1e-6)).powi(2);
    let phi = |a: [f64; 2], b: [f64; 2]| {
        (-((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)) / sigma2).exp()
    };
    // Interpolation system Φ c = d (symmetric positive definite for distinct centres).
    let mut a = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..m {
            a[i * m + j] = phi(centres[i], centres[j]);
        }
    }
    let missing: Vec<[f64; 2]> = vertices
        .iter()
        .zip(wanted)
        .map(|(&v, w)| [w[0] - y[v][0], w[1] - y[v][1]])
        .collect();
    let rhs: Vec<f64> = missing.iter().flatten().copied().collect();
    let Some(coef) = solve_dense(m, &a, &rhs, 2) else {
        for (&v, w) in vertices.iter().zip(wanted) {
            y[v] = [w[0], w[1], 0.0];
        }
        return;
    };
    for (v, p) in y.iter_mut().enumerate() {
        if boundary.loop_of[v] != u32::MAX {
            continue;
        }
        let z = [x[v][0], x[v][1]];
        for (c, k) in centres.iter().zip(coef.chunks_exact(2)) {
            let f = phi(z, *c);
            p[0] += f * k[0];
            p[1] += f * k[1];
        }
    }
    for (&v, w) in vertices.iter().zip(wanted) {
        y[v] = [w[0], w[1], 0.0];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;
    use crate::methods::deq::tests::{annulus_domain, quadrant_population};

    #[test]
    fn annulus_landmarks_reach_their_targets_bijectively() {
        let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
        let pop = quadrant_population(&mesh);
        let domain = annulus_domain(&mesh, 0.4);
        // Four vertices on the middle circle (radius 0.7), pulled a little clockwise and out.
        let ring = 6 * 96;
        let landmarks: Vec<usize> = (0..4).map(|k| ring + 12 + 24 * k).collect();
        let targets: Vec<[f64; 2]> = (0..4)
            .map(|k| {
                let a = std::f64::consts::TAU * (0.125 + 0.25 * k as f64) - 0.1;
                [0.75 * a.cos(), 0.75 * a.sin()]
            })
            .collect();
        let config = Config::default();
        let mut state = Deq::new(&mesh, &pop, &domain, &config.deq, &landmarks).unwrap();
        state.flow.area_weighted_gradient = true;
        let out = iterate(&state, &landmarks, &targets, &config, &mut |_| {}).unwrap();
        assert_eq!(count_nonpositive(&out.positions, &mesh.faces), 0);
        for (&v, q) in landmarks.iter().zip(&targets) {
            let p = out.positions[v];
            assert!((p[0] - q[0]).hypot(p[1] - q[1]) < 1e-12);
        }
        let var = state.flow.fit(&out.positions).var;
        assert!(var < 0.12, "Var {var}");
        assert_ne!(out.stop_reason, StopReason::MaxIter);
    }
}
