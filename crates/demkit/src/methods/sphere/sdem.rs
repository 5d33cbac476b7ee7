//! SDEM: spherical density-equalizing maps of genus-0 closed surfaces (Lyu, Lui & Choi,
//! Algorithm 3.1).
//!
//! 1. Initial map f₀: spherical conformal map with Möbius correction (§3.1.1).
//! 2. Repeat: rebuild A_n, L_n on the current sphere (3.7)–(3.8); one diffusion step (3.9);
//!    velocity −∇ρ/ρ (3.10)–(3.12) projected on the tangent planes (3.13); move (3.14) and
//!    renormalise onto the sphere; overlap correction (§3.1.3, in `sphere_overlap`); recouple the
//!    density to the moved map (3.22) — until sd(ρ_V)/mean(ρ_V) < ε.
//!
//! The step (`Config::dt`):
//! - **adaptive** (the default): the shared iteration's adaptive step with a search along each
//!   direction (`Step::Search`), where a step of length h diffuses the density for the time
//!   h and moves the map by h·v. A long step cancels every density mode at once (a mode of
//!   eigenvalue λ of the Laplacian moves by hλ/(1 + hλ) of the way), so the iteration is a
//!   Newton-like one on the density. The first try along each direction is at most the
//!   sphere's area 4π, the (4.39) bound at uniform density; a move that does not lower the
//!   merit is retried at half the length along the same velocity, one that does is tried up to
//!   three times twice as long. Maps are compared by the face misfit mean
//!   |log((A/ΣA)/(P/ΣP))|, which sees every face (ρ_V averages them at the vertices), and the
//!   run stops as stationary when the best misfit improved by less than 2% over 10 iterations.
//!   The diffusion operator is factored again only when the map's face areas have drifted
//!   (`fem::REFACTOR_DRIFT`).
//! - **fixed** δt (the paper's 0.1): every move kept. When a step had to be shortened to a
//!   fraction τ to stay bijective (`sphere_overlap`), the next velocity is taken from the
//!   density diffused for δt/τ instead of δt (doubling while the steps stay shorter than δt/8,
//!   at most 20 δt): the flow was too steep to follow there, and a smoother one lets the map
//!   move on; full steps bring the diffusion time back to δt. Maps are compared by
//!   sd(ρ_V)/mean(ρ_V); the run stops as stationary when its best fell by less than 6% over 10
//!   iterations (at that pace ε is out of reach within the iteration budget).
//!
//! The sign of (3.14) is the one that moves vertices along the velocity −∇ρ/ρ, from dense to
//! sparse regions (as in (2.4) and (3.3)). A run that stops as stationary returns the best map
//! met. The loop itself is the shared one of [`crate::methods::iteration`]; why the adaptive
//! step is the default is recorded in `docs/deviations.md`.

use super::density::{Density, SphereDiffusion};
use super::input::{SphereInput, check_sphere_input, initial_sphere_map};
use super::overlap::{OverlapCorrector, advance};
use crate::geometry::ellipsoid::Ellipsoid;
use crate::linalg::VertexOrder;
use crate::methods::MethodConfig;
use crate::methods::iteration::{
    Flow, Keep, Measured, Moved, Rules, Stationary, Step, check_parameters, iterate,
};
use crate::methods::{MapResult, ProgressFn, StopReason};
use crate::{Error, Result, TriMesh};
use std::time::Instant;

/// SDEM parameters; `Default` gives the paper's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Stop when sd/mean of the recoupled vertex density is below ε (paper: 1e-3).
    pub epsilon: f64,
    /// Iteration limit (paper: 200).
    pub max_iter: usize,
    /// A fixed time step δt (the paper uses 0.1); `None` adapts it (see the module docs).
    pub dt: Option<f64>,
}

/// The fixed step's stationary stop: the best sd/mean fell by less than 6% over 10 iterations.
const FIXED_STATIONARY: Stationary = Stationary::Best {
    window: 10,
    min_gain: 0.06,
};

/// The adaptive step's stationary window: the run stops when the best face misfit fell by less
/// than 2% over this many iterations.
const ADAPTIVE_WINDOW: usize = 10;

/// The adaptive step's stationary stop ([`ADAPTIVE_WINDOW`]).
const ADAPTIVE_STATIONARY: Stationary = Stationary::Best {
    window: ADAPTIVE_WINDOW,
    min_gain: 0.02,
};

/// An adaptive run that stalls with sd/mean of the vertex density at or above this many times ε
/// has not equalized it: the paper's fixed step takes over. Not when the map ends with local
/// area matching ([`Target::match_areas`]) and sd/mean of ρ_V is at most the face misfit: the
/// misfit left is then at the scale of single faces, which the vertex density does not see and
/// the matching removes.
const STALLED: f64 = 10.0;

/// The paper's time step δt, which takes over when the adaptive step stalls.
const PAPER_DT: f64 = 0.1;

impl Default for Config {
    fn default() -> Self {
        Self {
            epsilon: 1e-3,
            max_iter: 200,
            dt: None,
        }
    }
}

impl MethodConfig for Config {
    /// Computes the SDEM of `mesh` (a genus-0 closed surface) with one `population` value per face.
    /// The result lies on the unit sphere, in input vertex order.
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        let t0 = Instant::now();
        let input = SphereInput::new(mesh, population, self, "sdem")?;
        let (local, mesh, population, order) = input.parts();
        let mut notes = Vec::new();
        let initial = initial_sphere_map(mesh, population, order, &mut notes)?;
        if crate::init::spherical_conformal::count_spherical_flips(&initial, &mesh.faces) > 0 {
            return Err(Error::InvalidMesh(format!(
                "the mesh is too small to map onto the sphere: with {} faces its spherical \
             conformal map folds (subdivide it; the icosahedron's 20 faces are enough)",
                mesh.n_faces()
            )));
        }
        let time_init = t0.elapsed().as_secs_f64();
        let on = Target {
            domain: Ellipsoid::UNIT_SPHERE,
            method: "sdem",
            match_areas: false,
        };
        let mut result = equalize(on, mesh, population, initial, Some(order), self, progress)?;
        result.positions = local.restore_vertices(&result.positions);
        result.initial = local.restore_vertices(&result.initial);
        result.time_init = time_init;
        notes.append(&mut result.notes);
        result.notes = notes;
        Ok(result)
    }
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
    check_parameters(config.epsilon, config.dt, config.max_iter)?;
    check_sphere_input(mesh, population, "sdem")?;
    if initial.len() != mesh.n_vertices()
        || crate::init::spherical_conformal::count_spherical_flips(&initial, &mesh.faces) > 0
    {
        return Err(Error::Argument(
            "the initial spherical map must have one point per vertex and no flipped face".into(),
        ));
    }
    let on = Target {
        domain: Ellipsoid::UNIT_SPHERE,
        method: "sdem",
        match_areas: false,
    };
    equalize(on, mesh, population, initial, None, config, progress)
}

/// Where [`equalize`] maps and what it calls the result.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Target {
    /// The unit sphere (SDEM) or an ellipsoid (EDEM).
    pub domain: Ellipsoid,
    /// The method's report name.
    pub method: &'static str,
    /// Whether the map ends with local area matching ([`super::polish`]).
    pub match_areas: bool,
}

/// Algorithm 3.1 from `initial` on `on.domain` (the unit sphere, or an ellipsoid: the EDEM
/// paper's Algorithm 1 is the same iteration with the ellipsoid's normal and projection), the
/// inputs already checked by the caller; `order`: the mesh's elimination order, when the
/// caller has one.
pub(crate) fn equalize(
    on: Target,
    mesh: &TriMesh,
    population: &[f64],
    initial: Vec<[f64; 3]>,
    order: Option<&VertexOrder>,
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    let mut notes = Vec::new();
    let t1 = Instant::now();
    let faces = &mesh.faces;
    let mut flow = SphereFlow {
        diffusion: SphereDiffusion::new(on.domain, initial.len(), faces, population, order)?,
        corrector: OverlapCorrector::new(on.domain, &initial, faces),
        domain_area: on.domain.area(),
        faces,
        dt: config.dt,
        diffusion_time: config.dt.unwrap_or(0.0),
        moves: 0,
        corrected: 0,
    };
    let mut rules = Rules {
        epsilon: config.epsilon,
        max_iter: config.max_iter,
        step: Step::Search,
        stationary: Some(ADAPTIVE_STATIONARY),
        keep: Keep::Best,
    };
    let mut adaptive = None;
    if config.dt.is_none() {
        let out = iterate(&mut flow, initial.clone(), &rules, &mut *progress)?;
        let last = out.history.last().copied().unwrap_or(0.0);
        if out.stop_reason != StopReason::Stationary || last < STALLED * config.epsilon {
            return Ok(finish(on, out, initial, population, &flow, t1, notes));
        }
        // The best map's measure: the area matching's test below, and the comparison with the
        // fixed step's map.
        let best = flow.diffusion.measure(&out.map);
        if on.match_areas && best.sd_over_mean <= best.misfit {
            notes.push(format!(
                "the adaptive step stalled after {} iterations at sd/mean {:.3}, below the face \
                 misfit {:.3}: what is left alternates between neighbouring faces, for the local \
                 area matching",
                out.iterations, best.sd_over_mean, best.misfit
            ));
            return Ok(finish(on, out, initial, population, &flow, t1, notes));
        }
        // The face misfit stopped improving with the vertex density far from equal: the
        // paper's step from the start, and the better of the two maps.
        notes.push(format!(
            "the adaptive step stalled after {} iterations at sd/mean {last:.3}; the paper's \
             fixed step δt = {PAPER_DT} was run from the initial map too",
            out.iterations
        ));
        flow.dt = Some(PAPER_DT);
        flow.diffusion_time = PAPER_DT;
        rules.max_iter = config.max_iter.saturating_sub(out.iterations).max(1);
        adaptive = Some((out, best.misfit));
    }
    rules.step = Step::Fixed(flow.dt.unwrap_or(PAPER_DT));
    rules.stationary = Some(FIXED_STATIONARY);
    let mut out = iterate(&mut flow, initial.clone(), &rules, progress)?;
    if let Some((mut first, first_misfit)) = adaptive {
        first.iterations += out.iterations;
        first.history.append(&mut out.history);
        if flow.diffusion.measure(&out.map).misfit <= first_misfit {
            first.map = out.map;
            first.stop_reason = out.stop_reason;
        }
        out = first;
    }
    Ok(finish(on, out, initial, population, &flow, t1, notes))
}

/// The method's result from the iteration's outcome, with the overlap correction's note (and
/// the area matching, when `on` asks for it).
fn finish(
    on: Target,
    mut out: crate::methods::iteration::Outcome<Vec<[f64; 3]>>,
    initial: Vec<[f64; 3]>,
    population: &[f64],
    flow: &SphereFlow<'_>,
    t1: Instant,
    mut notes: Vec<String>,
) -> MapResult {
    if on.match_areas {
        let m = super::polish::match_areas(&on.domain, flow.faces, population, &mut out.map);
        if m.sweeps > 0 {
            notes.push(format!(
                "local area matching: {} sweeps took the face misfit from {:.4} to {:.4}",
                m.sweeps, m.misfit[0], m.misfit[1]
            ));
        }
    }
    notes.push(format!(
        "the diffusion operator was factored {} times in {} iterations",
        flow.diffusion.operator().factorizations(),
        out.iterations
    ));
    if flow.corrected > 0 {
        notes.push(format!(
            "the overlap correction was applied in {} of {} moves (a search tries several \
             moves per iteration)",
            flow.corrected, flow.moves
        ));
    }
    let positions = |x: Vec<[f64; 3]>| x.into_iter().map(|p| on.domain.project(p)).collect();
    out.into_result(on.method, initial, positions, t1, notes)
}

/// SDEM's flow (Alg. 3.1 lines 3–8) on the shared skeleton.
struct SphereFlow<'a> {
    diffusion: SphereDiffusion<'a>,
    corrector: OverlapCorrector,
    /// The domain's area: the adaptive step's longest step.
    domain_area: f64,
    faces: &'a [[u32; 3]],
    /// The fixed time step δt, or `None` for the adaptive step.
    dt: Option<f64>,
    /// With a fixed step, the time the density is diffused for before its velocity is taken
    /// (see the module docs): δt, longer after shortened steps.
    diffusion_time: f64,
    /// Moves tried, and those in which the overlap correction was applied.
    moves: usize,
    corrected: usize,
}

impl Flow for SphereFlow<'_> {
    type Map = Vec<[f64; 3]>;
    type Data = Density;

    /// The recoupled density (3.22): sd/mean of ρ_V is the stopping quantity; the merit is the
    /// face misfit with the adaptive step, sd/mean with a fixed one.
    fn measure(&mut self, x: &Vec<[f64; 3]>) -> Result<Measured<Density>> {
        let d = self.diffusion.measure(x);
        Ok(Measured {
            error: d.sd_over_mean,
            merit: match self.dt {
                Some(_) => d.sd_over_mean,
                None => d.misfit,
            },
            data: d,
        })
    }

    /// The adaptive step's longest step: the domain's area (4π on the sphere), the bound (4.39)
    /// at uniform density.
    fn step_cap(&self, _m: &Measured<Density>) -> f64 {
        self.domain_area
    }

    /// (3.9)–(3.14) and the overlap correction: one move of length `h` along the velocity.
    fn advance(
        &mut self,
        x: &Vec<[f64; 3]>,
        m: &Measured<Density>,
        h: f64,
    ) -> Result<Moved<Vec<[f64; 3]>>> {
        let diffusion_time = match self.dt {
            Some(_) => self.diffusion_time,
            None => h,
        };
        let mut direction = m.data.direction.borrow_mut();
        if self.dt.is_some() || direction.is_none() {
            *direction = Some(self.diffusion.velocity(x, &m.data, diffusion_time)?);
        }
        let v = direction.as_deref().unwrap_or_default();
        let step: Vec<[f64; 3]> = v.iter().map(|s| s.map(|c| c * h)).collect();
        drop(direction);
        let mut moved = x.clone();
        let outcome = advance(&mut moved, &step, self.faces, &self.corrector);
        self.moves += 1;
        self.corrected += outcome.corrected as usize;
        let Some(dt) = self.dt else {
            return Ok(Moved {
                map: moved,
                fraction: outcome.fraction,
            });
        };
        // A step that had to be shortened to the fraction τ met a flow too steep to follow:
        // the next velocity comes from a density diffused for δt/τ, which smooths the flow
        // there; while steps stay very short (τ ≤ 1/8) the diffusion time keeps doubling
        // (at most 20 δt); full steps halve it back towards δt.
        self.diffusion_time = if outcome.fraction >= 1.0 {
            (0.5 * self.diffusion_time).max(dt)
        } else if outcome.fraction <= 0.125 {
            (2.0 * self.diffusion_time)
                .max(dt / outcome.fraction.max(1e-3))
                .min(20.0 * dt)
        } else {
            (dt / outcome.fraction).min(20.0 * dt)
        };
        Ok(Moved {
            map: moved,
            fraction: outcome.fraction,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;
    use crate::methods::StopReason;
    use crate::metrics::{Domain, compute};

    /// SDEM at the defaults from the identity map of `mesh` (a unit sphere) instead of its
    /// spherical conformal map.
    fn from_identity(mesh: &TriMesh, pop: &[f64]) -> MapResult {
        run_from(
            mesh,
            pop,
            mesh.positions.clone(),
            &Config::default(),
            &mut |_| {},
        )
        .unwrap()
    }

    /// The population `area · density(centroid)` of every face of `mesh`.
    pub(crate) fn area_times(mesh: &TriMesh, density: impl Fn([f64; 3]) -> f64) -> Vec<f64> {
        let area = face_areas(&mesh.positions, &mesh.faces);
        mesh.faces
            .iter()
            .zip(&area)
            .map(|(f, a)| {
                let p = f.map(|v| mesh.positions[v as usize]);
                a * density(std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0))
            })
            .collect()
    }

    #[test]
    fn equal_density_stops_at_once() {
        // The icosphere onto itself with its own face areas as population: ρ is exactly 1.
        let mesh = icosphere(3).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let r = from_identity(&mesh, &pop);
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
        let pop = area_times(&mesh, |c| 1.0 + 4.5 * (c[2] + 1.0));
        let r = Config::default().run(&mesh, &pop, &mut |_| {}).unwrap();
        assert!(r.converged);
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(m.density_var_final <= 1e-4, "{m:?}");
        // From the identity map the density is far from equal; the flow equalizes it too.
        let r = from_identity(&mesh, &pop);
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert!(m.density_var_initial > 0.1, "{m:?}");
        assert!(m.density_var_final <= 1e-4, "{m:?}");
        assert_eq!(m.flipped_triangles, 0);
        for p in &r.positions {
            assert!((crate::geometry::norm(*p) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn the_papers_fixed_step_equalizes_too() {
        let mesh = icosphere(3).unwrap();
        let pop = area_times(&mesh, |c| 2.0 + c[0]);
        let fixed = Config {
            dt: Some(0.1),
            ..Config::default()
        };
        let r = run_from(&mesh, &pop, mesh.positions.clone(), &fixed, &mut |_| {}).unwrap();
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert!(r.converged && m.flipped_triangles == 0, "{m:?}");
        assert!(m.density_var_final < 1e-3 * m.density_var_initial, "{m:?}");
        // The adaptive default judges maps by the face misfit: it ends at least as low.
        let a = from_identity(&mesh, &pop);
        let ma = compute(&mesh, &pop, &a.initial, &a.positions, Domain::Sphere, None);
        assert!(
            ma.density_error_mean <= m.density_error_mean,
            "{ma:?} {m:?}"
        );
    }

    #[test]
    fn a_disk_is_refused() {
        let disk = crate::generate::regular_polygon(12, 3).unwrap();
        let pop = face_areas(&disk.positions, &disk.faces);
        let e = Config::default().run(&disk, &pop, &mut |_| {}).unwrap_err();
        assert!(matches!(e, Error::Topology { .. }), "{e}");
    }
}
