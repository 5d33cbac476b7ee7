//! TDEM: density-equalizing maps of the torus (Yao & Choi, Algorithm 1), and through them the
//! toroidal parameterization of genus-one surfaces (Algorithm 2).
//!
//! 1. The initial map on the flat torus `[0, 2πR) × [−πr, πr)`: φ⁻¹ (9)–(10) of a mesh that
//!    lies on the target torus, otherwise the periodic harmonic map of `init::genus_one`.
//! 2. Repeat: the modified density `ρ̃ = P / Area(φ(T))` (11), (26) at the vertices, one
//!    backward-Euler diffusion step on the periodic plane (16), its gradient (19)–(20), the
//!    velocity `v = −∇ρ̃/ρ̃` (22) and the move `x ← x + δt v` (23); a move that folds triangles
//!    is rebuilt by the periodic LBS from its truncated Beltrami coefficient (the overlap
//!    correction, Alg. 1 line 7), and shortened if that does not unfold them; until
//!    `sd(ρ̃)/mean(ρ̃) < ε`.
//! 3. The result is `φ` of the flat map.
//!
//! The flat torus is stored as a point per vertex plus a lattice translation per face corner
//! (`FlatTorusMap`), so the operators are periodic by construction and opposite sides of the
//! period rectangle stay translates of each other (24)–(25) exactly, without fixing the cut.
//!
//! Time step: the paper's fixed δt = 0.1 needs 23–228 iterations on its examples. A
//! backward-Euler step of length δt damps a density mode of wavenumber k by `1/(1 + δt k²)`
//! and the move cancels the fraction `δt k²/(1 + δt k²)` of it, so a long step cancels every
//! mode at once — the iteration becomes a Newton-like one on the density. The step is the
//! shared iteration's adaptive one ([`crate::methods::iteration`]), capped by the DEM paper's (4.39) for
//! the current density on the period rectangle: a move that does not lower sd/mean is undone
//! and the step halved; after one that does, the step may double.

use crate::fem::{DiffusionOperator, UnfoldedFaces, VertexFaces, lumped_mass};
use crate::geometry::face_areas;
use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::mesh::topology::topology;
use crate::methods::disk::planar_diffusion::collapse_time;
use crate::methods::iteration::check_parameters;
use crate::methods::iteration::{
    Flow, Keep, Measured, Moved, Rules, Step, diffusion_time_step, iterate,
};
use crate::methods::{MapResult, ProgressFn, StopReason};
use crate::metrics::normalized_variance;
use crate::qc::{PeriodicBeltramiSolver, beltrami_coefficient, truncate};
use crate::{Error, Result, TriMesh};
use rayon::prelude::*;
use std::time::Instant;

/// TDEM parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// A fixed time step δt (the paper uses 0.1); `None` adapts it (see the module docs).
    pub dt: Option<f64>,
    /// Stop when sd/mean of the density on the torus falls below ε (the authors' code: 1e-2).
    pub epsilon: f64,
    /// Iteration limit (paper: 1000).
    pub max_iter: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            dt: None,
            epsilon: 1e-2,
            max_iter: 1000,
        }
    }
}

/// Truncation margin δ of the overlap correction: folded faces get |μ| = 1 − δ.
const TRUNCATION: f64 = 0.1;

/// A vertex farther than this (times r) from the torus means the mesh is not on it.
const ON_TORUS: f64 = 1e-6;

/// Checks that `mesh` is a closed connected genus-one surface and `population` fits it.
pub(crate) fn torus_input(mesh: &TriMesh, population: &[f64]) -> Result<()> {
    crate::methods::require_valid_mesh(mesh, "tdem")?;
    let topo = topology(mesh);
    if topo.components != 1 || !topo.boundary_loops.is_empty() || topo.genus != 1 {
        let what = if topo.components != 1 {
            format!("a mesh of {} separate pieces", topo.components)
        } else if !topo.boundary_loops.is_empty() {
            format!(
                "an open surface with {} boundary loops",
                topo.boundary_loops.len()
            )
        } else {
            format!("a closed surface of genus {}", topo.genus)
        };
        return Err(Error::Topology {
            method: "tdem".into(),
            msg: format!("tdem needs a closed connected surface of genus one, but this is {what}"),
        });
    }
    crate::population::check_population(population, mesh.n_faces())
}

/// The initial map on the flat torus: φ⁻¹ of a mesh lying on `torus` (Alg. 1 line 1), or the
/// periodic harmonic map of any other genus-one mesh (Alg. 2 line 1).
pub fn initial_map(mesh: &TriMesh, torus: &Torus) -> Result<FlatTorusMap> {
    let far = mesh
        .positions
        .iter()
        .map(|&p| torus.distance(p))
        .fold(0.0, f64::max);
    if far <= ON_TORUS * torus.minor {
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, torus);
        if map.count_flipped(&mesh.faces, torus.periods()) == 0 {
            return Ok(map);
        }
    }
    crate::init::genus_one::flat_torus_map(mesh, torus)
}

/// Computes the TDEM map of the genus-one `mesh` onto `torus` with one `population` value per
/// face. The result lies on the torus, in input vertex order.
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    torus: &Torus,
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_parameters(config.epsilon, config.dt, config.max_iter)?;
    torus_input(mesh, population)?;
    let t0 = Instant::now();
    let initial = initial_map(mesh, torus)?;
    let time_init = t0.elapsed().as_secs_f64();
    let mut result = run_from(mesh, population, torus, &initial, config, progress)?;
    result.time_init = time_init;
    Ok(result)
}

/// What TDEM measures on a flat map.
struct TorusDensity {
    unfolded: UnfoldedFaces,
    /// Planar face areas.
    areas: Vec<f64>,
    /// The modified density (11) at the vertices, W^FV with the planar areas (21).
    rho_v: Vec<f64>,
}

/// TDEM's flow (Alg. 1 lines 3–8) on the shared skeleton.
struct TorusFlow<'a> {
    faces: &'a [[u32; 3]],
    population: &'a [f64],
    torus: &'a Torus,
    incidence: VertexFaces,
    diffusion: DiffusionOperator,
    lbs: PeriodicBeltramiSolver,
    /// The initial map unfolded: the source of the overlap correction's Beltrami coefficients.
    source: UnfoldedFaces,
    /// What the moves had to do to stay unfolded, each said once.
    notes: Vec<String>,
}

impl Flow for TorusFlow<'_> {
    type Map = FlatTorusMap;
    type Data = TorusDensity;

    /// sd/mean of the density on the torus at the vertices (W^FV with the torus areas) is
    /// both the stopping quantity and the merit.
    fn measure(&mut self, map: &FlatTorusMap) -> Result<Measured<TorusDensity>> {
        let period = self.torus.periods();
        let unfolded = UnfoldedFaces::new(map, self.faces, period);
        let areas = unfolded.signed_areas();
        let torus_areas = face_areas(&map.on_torus(self.torus), self.faces);
        let rho_f: Vec<f64> = self
            .population
            .iter()
            .zip(&torus_areas)
            .map(|(p, a)| p / a.max(f64::MIN_POSITIVE))
            .collect();
        let sd_over_mean = normalized_variance(&self.incidence.apply(&torus_areas, &rho_f)).sqrt();
        Ok(Measured {
            error: sd_over_mean,
            merit: sd_over_mean,
            data: TorusDensity {
                rho_v: self.incidence.apply(&areas, &rho_f),
                unfolded,
                areas,
            },
        })
    }

    /// δt of (4.39) for the current density on the period rectangle.
    fn step_cap(&self, m: &Measured<TorusDensity>) -> f64 {
        let period = self.torus.periods();
        diffusion_time_step(&m.data.rho_v, period[0] * period[1])
    }

    /// (16) `(A + h L) ρ̃ = A ρ̃` on the periodic plane, (19)–(22) the velocity, (23) the move,
    /// kept unfolded by [`move_without_folds`].
    fn advance(
        &mut self,
        map: &FlatTorusMap,
        m: &Measured<TorusDensity>,
        h: f64,
    ) -> Result<Moved<FlatTorusMap>> {
        let TorusDensity {
            unfolded,
            areas,
            rho_v,
        } = &m.data;
        let (faces, n) = (self.faces, map.points.len());
        let mass = lumped_mass(n, faces, areas);
        let rho = self
            .diffusion
            .factor_weights(&unfolded.cotangent_weights(), mass, h, &[])?
            .diffuse(rho_v)?;
        let grad = self
            .incidence
            .apply_vec(areas, &unfolded.gradient(faces, &rho));
        let step: Vec<[f64; 2]> = grad
            .iter()
            .zip(&rho)
            .map(|(g, r)| [-h * g[0] / r, -h * g[1] / r])
            .collect();
        let period = self.torus.periods();
        let (moved, fraction, how) =
            move_without_folds(map, unfolded, &step, faces, period, &self.source, &self.lbs)?;
        if let Some(note) = how.filter(|n| !self.notes.contains(n)) {
            self.notes.push(note);
        }
        Ok(Moved {
            map: moved,
            fraction,
        })
    }
}

/// Algorithm 1 from the flip-free flat map `initial`.
pub fn run_from(
    mesh: &TriMesh,
    population: &[f64],
    torus: &Torus,
    initial: &FlatTorusMap,
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_parameters(config.epsilon, config.dt, config.max_iter)?;
    torus_input(mesh, population)?;
    let faces = &mesh.faces[..];
    let n = mesh.n_vertices();
    let period = torus.periods();
    if initial.points.len() != n
        || initial.offsets.len() != faces.len()
        || initial.count_flipped(faces, period) > 0
    {
        return Err(Error::Argument(
            "the initial flat torus map must have one point per vertex and no flipped face".into(),
        ));
    }
    let t1 = Instant::now();
    let mut flow = TorusFlow {
        faces,
        population,
        torus,
        incidence: VertexFaces::new(n, faces),
        diffusion: DiffusionOperator::new(n, faces)?,
        lbs: PeriodicBeltramiSolver::new(n, faces)?,
        source: UnfoldedFaces::new(initial, faces, period),
        notes: Vec::new(),
    };
    let rules = Rules {
        epsilon: config.epsilon,
        max_iter: config.max_iter,
        step: config.dt.map_or(Step::Adaptive, Step::Fixed),
        // No window: torus_4's unsmooth population needs 320 iterations with slow stretches
        // (docs/deviations.md, the shared iteration); TDEM stops as stationary only when its
        // adaptive step has vanished.
        stationary: None,
        keep: Keep::Best,
    };
    let out = iterate(&mut flow, initial.clone(), &rules, progress)?;
    let mut notes = flow.notes;
    if out.stop_reason == StopReason::Stationary {
        notes.push(format!(
            "stopped after {} iterations: no step lowered sd/mean of the density below {:.3e}",
            out.iterations,
            out.history.iter().copied().fold(f64::INFINITY, f64::min)
        ));
    }
    let mut result = MapResult::new(
        "tdem",
        out.map.on_torus(torus),
        initial.on_torus(torus),
        out.stop_reason,
        out.iterations,
        out.history,
    );
    result.time_map = t1.elapsed().as_secs_f64();
    result.notes = notes;
    result.flat_torus = Some(out.map);
    Ok(result)
}

/// The move `map + step` without folded faces: as it is if nothing folds; else rebuilt by the
/// periodic LBS from the move's Beltrami coefficient truncated below 1 (the overlap
/// correction); else, if that still folds, the move scaled down to half the time at which its
/// first triangle would collapse (`collapse_time`), which never folds. Returns the new map, the
/// fraction of the step it moved (1 unless shortened) and a note when the move had to be
/// corrected. `now` is `map` unfolded.
#[allow(clippy::too_many_arguments)]
fn move_without_folds(
    map: &FlatTorusMap,
    now: &UnfoldedFaces,
    step: &[[f64; 2]],
    faces: &[[u32; 3]],
    period: [f64; 2],
    source: &UnfoldedFaces,
    lbs: &PeriodicBeltramiSolver,
) -> Result<(FlatTorusMap, f64, Option<String>)> {
    let shifted = |tau: f64| FlatTorusMap {
        points: map
            .points
            .iter()
            .zip(step)
            .map(|(p, s)| [p[0] + tau * s[0], p[1] + tau * s[1]])
            .collect(),
        offsets: map.offsets.clone(),
    };
    let full = shifted(1.0);
    if full.count_flipped(faces, period) == 0 {
        return Ok((full, 1.0, None));
    }
    let target = UnfoldedFaces::new(&full, faces, period);
    let mu: Vec<_> = beltrami_coefficient(&source.points, &target.points, &source.faces)
        .into_iter()
        .map(|m| truncate(m, TRUNCATION))
        .collect();
    let corrected = lbs.solve(source, &mu, &map.offsets, period, full.points[0])?;
    if corrected.count_flipped(faces, period) == 0 {
        return Ok((
            corrected,
            1.0,
            Some("folded triangles were rebuilt by the Beltrami overlap correction".into()),
        ));
    }
    let t_min = now
        .faces
        .par_iter()
        .zip(faces.par_iter())
        .map(|(local, f)| {
            let p = local.map(|c| now.points[c as usize]);
            collapse_time(p, f.map(|v| step[v as usize]))
        })
        .reduce(|| f64::INFINITY, f64::min);
    let fraction = (0.5 * t_min).min(1.0);
    Ok((
        shifted(fraction),
        fraction,
        Some("a step that folded triangles was shortened".into()),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::torus;
    use crate::metrics::{Domain, compute};

    /// The population `f(u, v) · Area(T)` of every face, with (u, v) its centroid under φ⁻¹.
    fn population(mesh: &TriMesh, t: &Torus, f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        let areas = face_areas(&mesh.positions, &mesh.faces);
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, t);
        (0..mesh.n_faces())
            .map(|i| {
                let c = map.corners(&mesh.faces, i, t.periods());
                let (u, v) = (
                    (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                    (c[0][1] + c[1][1] + c[2][1]) / 3.0,
                );
                f(u / t.major, v / t.minor) * areas[i]
            })
            .collect()
    }

    fn check(mesh: &TriMesh, t: &Torus, pop: &[f64]) -> crate::metrics::Metrics {
        let r = run(mesh, pop, t, &Config::default(), &mut |_| {}).unwrap();
        assert!(r.converged, "{:?} after {}", r.stop_reason, r.iterations);
        let flat = r.flat_torus.as_ref().unwrap();
        let flipped = flat.count_flipped(&mesh.faces, t.periods());
        assert_eq!(flipped, 0);
        for p in &r.positions {
            assert!(t.distance(*p) < 1e-9);
        }
        compute(
            mesh,
            pop,
            &r.initial,
            &r.positions,
            Domain::Torus { flipped },
            None,
        )
    }

    #[test]
    fn equalizes_the_papers_smooth_populations() {
        // Fig. 5: P = 2 − cos u on (3, 1); Fig. 7: P = 1.2 − sin u sin v.
        let t = Torus::new(3.0, 1.0).unwrap();
        let mesh = torus(3.0, 1.0, 60, 20).unwrap();
        for f in [
            &(|u: f64, _v: f64| 2.0 - u.cos()) as &dyn Fn(f64, f64) -> f64,
            &|u: f64, v: f64| 1.2 - u.sin() * v.sin(),
        ] {
            let pop = population(&mesh, &t, f);
            let m = check(&mesh, &t, &pop);
            assert!(m.density_var_initial > 0.05);
            assert!(m.density_var_final < 1e-4, "{}", m.density_var_final);
        }
    }

    #[test]
    fn uniform_density_does_not_move() {
        let t = Torus::new(2.0, 1.0).unwrap();
        let mesh = torus(2.0, 1.0, 40, 20).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let r = run(&mesh, &pop, &t, &Config::default(), &mut |_| {}).unwrap();
        assert_eq!(r.iterations, 0);
        for (a, b) in r.positions.iter().zip(&mesh.positions) {
            assert!((a[0] - b[0]).abs() + (a[1] - b[1]).abs() + (a[2] - b[2]).abs() < 1e-12);
        }
    }

    #[test]
    fn wrong_topology_and_bad_populations_are_errors() {
        let t = Torus::new(2.0, 1.0).unwrap();
        let sphere = crate::generate::icosphere(2).unwrap();
        let pop = vec![1.0; sphere.n_faces()];
        let e = run(&sphere, &pop, &t, &Config::default(), &mut |_| {}).unwrap_err();
        assert!(matches!(e, Error::Topology { .. }), "{e}");
        let mesh = torus(2.0, 1.0, 12, 6).unwrap();
        for bad in [vec![1.0; 3], vec![-1.0; mesh.n_faces()]] {
            assert!(run(&mesh, &bad, &t, &Config::default(), &mut |_| {}).is_err());
        }
    }
}
