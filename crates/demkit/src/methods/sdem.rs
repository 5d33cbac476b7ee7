//! SDEM: spherical density-equalizing maps of genus-0 closed surfaces (Lyu, Lui & Choi,
//! Algorithm 3.1).
//!
//! 1. Initial map f₀: spherical conformal map with Möbius correction (§3.1.1).
//! 2. Repeat: rebuild A_n, L_n on the current sphere (3.7)–(3.8); one diffusion step (3.9);
//!    velocity −∇ρ/ρ (3.10)–(3.12) projected on the tangent planes (3.13); move (3.14) and
//!    renormalise onto the sphere; overlap correction (§3.1.3, in `sphere_overlap`); recouple the
//!    density to the moved map (3.22) — until sd(ρ_V)/mean(ρ_V) < ε.
//!
//! When a step had to be shortened to a fraction τ to stay bijective (`sphere_overlap`), the
//! next velocity is taken from the density diffused for δt/τ instead of δt (doubling while the
//! steps stay shorter than δt/8, at most 20 δt):
//! the flow was too steep to follow there, and a smoother one lets the map move on; full steps
//! bring the diffusion time back to δt, so maps that never need short steps follow the paper.
//!
//! The sign of (3.14) is the one that moves vertices along the velocity −∇ρ/ρ, from dense to
//! sparse regions (as in (2.4) and (3.3)). When the density stops improving before ε is met
//! (over the last 10 iterations sd/mean fell by less than 6%: the discrete map cannot
//! equalize further at a useful pace) the iteration stops as stationary and returns the best
//! map met.

use super::dem::check_config_values;
use super::sphere_density::SphereDiffusion;
use super::sphere_input::{check_sphere_input, initial_sphere_map};
use super::sphere_overlap::{OverlapCorrector, advance};
use super::{MapResult, Progress, ProgressFn, StopReason};
use crate::geometry::sphere::normalize;
use crate::{Error, Result, TriMesh};
use std::time::Instant;

/// SDEM parameters; `Default` gives the paper's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Stop when sd/mean of the recoupled vertex density is below ε (paper: 1e-3).
    pub epsilon: f64,
    /// Iteration limit (paper: 200).
    pub max_iter: usize,
    /// Time step δt (paper: 0.1).
    pub dt: f64,
    /// Stationary stop: the iteration stops when, over the last `window` iterations, the
    /// stopping quantity fell by less than the fraction `min_progress` (at that pace ε is out
    /// of reach within the iteration budget).
    pub window: usize,
    /// See `window`.
    pub min_progress: f64,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            epsilon: 1e-3,
            max_iter: 200,
            dt: 0.1,
            window: 10,
            min_progress: 0.06,
        }
    }
}

/// Computes the SDEM of `mesh` (a genus-0 closed surface) with one `population` value per face.
/// The result lies on the unit sphere, in input vertex order.
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_config_values(config.epsilon, Some(config.dt), config.max_iter)?;
    check_sphere_input(mesh, population, "sdem")?;
    let t0 = Instant::now();
    let mut notes = Vec::new();
    let initial = initial_sphere_map(mesh, population, &mut notes)?;
    if crate::init::spherical_conformal::count_spherical_flips(&initial, &mesh.faces) > 0 {
        return Err(Error::InvalidMesh(format!(
            "the mesh is too small to map onto the sphere: with {} faces its spherical \
             conformal map folds (subdivide it; the icosahedron's 20 faces are enough)",
            mesh.n_faces()
        )));
    }
    let time_init = t0.elapsed().as_secs_f64();
    let mut result = run_from(mesh, population, initial, config, progress)?;
    result.time_init = time_init;
    notes.append(&mut result.notes);
    result.notes = notes;
    Ok(result)
}

/// Algorithm 3.1 from a given flip-free initial map `initial` (unit vectors, faces
/// counter-clockwise seen from outside) instead of the spherical conformal map.
pub fn run_from(
    mesh: &TriMesh,
    population: &[f64],
    initial: Vec<[f64; 3]>,
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_config_values(config.epsilon, Some(config.dt), config.max_iter)?;
    check_sphere_input(mesh, population, "sdem")?;
    if initial.len() != mesh.n_vertices()
        || crate::init::spherical_conformal::count_spherical_flips(&initial, &mesh.faces) > 0
    {
        return Err(Error::Argument(
            "the initial spherical map must have one point per vertex and no flipped face".into(),
        ));
    }
    let mut notes = Vec::new();
    let t1 = Instant::now();
    let faces = &mesh.faces;
    let diffusion = SphereDiffusion::new(initial.len(), faces, population)?;
    let corrector = OverlapCorrector::new(&initial, faces);
    let mut x = initial.clone();
    let mut d = diffusion.measure(&x);
    let mut history = Vec::new();
    let mut best = (d.sd_over_mean, x.clone());
    let mut stop_reason = StopReason::MaxIter;
    let mut iterations = 0;
    let mut corrected = 0usize;
    let mut diffusion_time = config.dt;
    if d.sd_over_mean < config.epsilon {
        stop_reason = StopReason::Tolerance;
    } else {
        for it in 1..=config.max_iter {
            iterations = it;
            let v = diffusion.velocity(&x, &d, diffusion_time)?;
            let step: Vec<[f64; 3]> = v.iter().map(|s| s.map(|c| c * config.dt)).collect();
            let outcome = advance(&mut x, &step, faces, &corrector);
            // A step that had to be shortened to the fraction τ met a flow too steep to follow:
            // the next velocity comes from a density diffused for δt/τ, which smooths the flow
            // there; while steps stay very short (τ ≤ 1/8) the diffusion time keeps doubling
            // (at most 20 δt); full steps halve it back towards δt.
            diffusion_time = if outcome.fraction >= 1.0 {
                (0.5 * diffusion_time).max(config.dt)
            } else if outcome.fraction <= 0.125 {
                (2.0 * diffusion_time)
                    .max(config.dt / outcome.fraction.max(1e-3))
                    .min(20.0 * config.dt)
            } else {
                (config.dt / outcome.fraction).min(20.0 * config.dt)
            };
            corrected += outcome.corrected as usize;
            d = diffusion.measure(&x);
            history.push(d.sd_over_mean);
            progress(Progress {
                iteration: it,
                max_iter: config.max_iter,
                error: d.sd_over_mean,
            });
            if d.sd_over_mean < best.0 {
                best = (d.sd_over_mean, x.clone());
            }
            if d.sd_over_mean < config.epsilon {
                stop_reason = StopReason::Tolerance;
                best.1 = x.clone();
                break;
            }
            let stalled = history.len() > config.window
                && best.0
                    > (1.0 - config.min_progress) * history[history.len() - 1 - config.window];
            if stalled || outcome.fraction == 0.0 {
                stop_reason = StopReason::Stationary;
                break;
            }
        }
    }
    if corrected > 0 {
        notes.push(format!(
            "the overlap correction was applied in {corrected} iterations"
        ));
    }
    let positions = best.1.into_iter().map(normalize).collect();
    Ok(MapResult {
        flat_torus: None,
        refined: None,
        objective: None,
        method: "sdem",
        positions,
        initial,
        converged: stop_reason != StopReason::MaxIter,
        stop_reason,
        iterations,
        history,
        time_init: 0.0,
        time_map: t1.elapsed().as_secs_f64(),
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;
    use crate::metrics::{Domain, compute};

    #[test]
    fn equal_density_stops_at_once() {
        // The icosphere onto itself with its own face areas as population: ρ is exactly 1.
        let mesh = icosphere(3).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let r = run_from(
            &mesh,
            &pop,
            mesh.positions.clone(),
            &Config::default(),
            &mut |_| {},
        )
        .unwrap();
        assert_eq!(r.iterations, 0);
        assert_eq!(r.stop_reason, StopReason::Tolerance);
        for (a, b) in r.positions.iter().zip(&mesh.positions) {
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-15));
        }
    }

    #[test]
    fn smooth_tenfold_population_is_equalized() {
        // Density varying smoothly by a factor 10 from the south to the north pole.
        let mesh = icosphere(4).unwrap();
        let area = face_areas(&mesh.positions, &mesh.faces);
        let pop: Vec<f64> = mesh
            .faces
            .iter()
            .zip(&area)
            .map(|(f, a)| {
                let z = f
                    .iter()
                    .map(|&v| mesh.positions[v as usize][2])
                    .sum::<f64>()
                    / 3.0;
                a * (1.0 + 4.5 * (z + 1.0))
            })
            .collect();
        let r = run(&mesh, &pop, &Config::default(), &mut |_| {}).unwrap();
        assert!(r.converged);
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(m.density_var_final <= 1e-4, "{m:?}");
        // From the identity map the density is far from equal; the flow equalizes it too.
        let r = run_from(
            &mesh,
            &pop,
            mesh.positions.clone(),
            &Config::default(),
            &mut |_| {},
        )
        .unwrap();
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert!(m.density_var_initial > 0.1, "{m:?}");
        assert!(m.density_var_final <= 1e-4, "{m:?}");
        assert_eq!(m.flipped_triangles, 0);
        for p in &r.positions {
            assert!((crate::geometry::norm(*p) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_disk_is_refused() {
        let disk = crate::generate::regular_polygon(12, 3).unwrap();
        let pop = face_areas(&disk.positions, &disk.faces);
        let e = run(&disk, &pop, &Config::default(), &mut |_| {}).unwrap_err();
        assert!(matches!(e, Error::Topology { .. }), "{e}");
    }
}
