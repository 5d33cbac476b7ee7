//! DEQ: bijective density-equalizing quasiconformal maps of multiply connected open surfaces
//! (and disks) onto circle domains (Lyu, Choi & Lui, Algorithm 5.3).
//!
//! 1. Initial conformal map g₀ onto a circle domain D⁰ (§5.1.1, `init::circle_domain`).
//! 2. Repeat: geometry modification (GM, Alg. 5.1) — the holes move, grow and turn by the
//!    fit of the density velocity plus the Beltrami terms (5.28), and the domain is rebuilt by
//!    LBS from the relaxed ν (5.34) —; then Beltrami density-equalizing descent (BDED,
//!    Alg. 5.2) — every vertex moves by δt v, boundary vertices sliding on their circles, the
//!    Beltrami coefficient of that move is relaxed (5.41)–(5.42), cut off (5.43) and the map
//!    rebuilt by LBS (5.44) with the circles fixed — until |E_n − E_{n−1}| < ε.
//!
//! Every map is a map of D⁰: LBS always starts from D⁰ with the current Beltrami coefficient,
//! so the result is `f = g_N ∘ g₀` (5.45). Bijectivity: the cut-off keeps |ν| < 1, and a
//! reconstruction that still flips a triangle (LBS is exact only in the continuum) is redone
//! with half the step. Without holes (a disk) GM has nothing to move and DEQ is BDED alone,
//! as §6.1 prescribes for simply connected surfaces.

use super::beltrami_descent::{Relaxation, slide_boundary};
use super::circle_flow::{Circle, CircleBoundary, DensityFlow, Fit, FlowState};
use super::dem::check_config_values;
use super::geometry_modification::HoleTerms;
use super::{MapResult, Progress, ProgressFn, StopReason};
use crate::fem::VertexFaces;
use crate::geometry::count_nonpositive;
use crate::geometry::face_areas;
use crate::init::circle_domain::{CircleDomain, circle_domain_map};
use crate::init::disk_mobius::balance_areas;
use crate::mesh::topology::topology;
use crate::qc::{LinearBeltramiSolver, beltrami_coefficient};
use crate::{Error, Result, TriMesh};
use num_complex::Complex64;
use std::time::Instant;

/// DEQ parameters; `Default` gives the paper's values (§6).
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Weight α of `∫|ν|²` (paper: 0.1).
    pub alpha: f64,
    /// Weight β of `∫|∇ν|²` (paper: 0.05).
    pub beta: f64,
    /// Time step δt (paper: 0.1).
    pub dt: f64,
    /// Stop when |E_n − E_{n−1}| < ε (paper: 1e-2).
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Run the geometry modification (false: the shape-preserving DEQ of §5.1.4).
    pub geometry_update: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            alpha: 0.1,
            beta: 0.05,
            dt: 0.1,
            epsilon: 1e-2,
            max_iter: 500,
            geometry_update: true,
        }
    }
}

/// How many times a step is halved before giving up on it.
const MAX_HALVINGS: usize = 8;

/// The diffusion time bound in mean face areas (see `Deq::diffusion_time`).
const SMOOTHING_FACES: f64 = 10.0;

/// The diffusion time bound as a fraction of the domain's area.
const SMOOTHING_AREA: f64 = 1.0 / 400.0;

/// Iterations over which Var(ρ̃) must improve by [`STATIONARY_GAIN`].
const STATIONARY_WINDOW: usize = 8;

/// See [`STATIONARY_WINDOW`].
const STATIONARY_GAIN: f64 = 0.05;

/// Checks that `mesh` is a connected open surface of genus 0 (a disk or a disk with holes)
/// and `population` has one positive value per face; returns its boundary loops.
pub(crate) fn circle_input(
    mesh: &TriMesh,
    population: &[f64],
    method: &str,
) -> Result<Vec<Vec<u32>>> {
    let topo = topology(mesh);
    if topo.components != 1 || topo.boundary_loops.is_empty() || topo.genus != 0 {
        let what = if topo.boundary_loops.is_empty() {
            format!("a closed surface of genus {}", topo.genus)
        } else if topo.components != 1 {
            format!("a mesh of {} separate pieces", topo.components)
        } else {
            format!(
                "a surface of genus {} with {} boundary loops",
                topo.genus,
                topo.boundary_loops.len()
            )
        };
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!(
                "{method} needs a connected open surface of genus 0 (a disk, possibly with holes), but this is {what}"
            ),
        });
    }
    crate::population::check_population(population, mesh.n_faces())?;
    Ok(topo.boundary_loops)
}

/// The initial map of DEQ and LDEQ (§5.1.1): the conformal map onto a circle domain, composed
/// with the disk automorphism that best matches its face areas to the population
/// (`init::disk_mobius`; still conformal).
pub(crate) fn initial_circle_domain(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    population: &[f64],
) -> Result<CircleDomain> {
    let domain = circle_domain_map(mesh, loops)?;
    Ok(balance_areas(&domain, &mesh.faces, population))
}

pub(crate) fn check_config(c: &Config) -> Result<()> {
    check_config_values(c.epsilon, Some(c.dt), c.max_iter)?;
    for (name, v) in [("--alpha", c.alpha), ("--beta", c.beta)] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err(Error::Argument(format!(
                "{name} must be zero or positive, got {v}"
            )));
        }
    }
    Ok(())
}

/// Computes the DEQ map of `mesh` (a connected open genus-0 surface) with one `population`
/// value per face. The result lies in the unit disk (z = 0), in input vertex order.
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_config(config)?;
    let loops = circle_input(mesh, population, "deq")?;
    let t0 = Instant::now();
    let domain = initial_circle_domain(mesh, &loops, population)?;
    let time_init = t0.elapsed().as_secs_f64();
    let mut result = run_from(mesh, population, &domain, config, progress)?;
    result.time_init = time_init;
    Ok(result)
}

/// Algorithm 5.3 from a given flip-free circle domain map (instead of the conformal one).
pub fn run_from(
    mesh: &TriMesh,
    population: &[f64],
    domain: &CircleDomain,
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_config(config)?;
    circle_input(mesh, population, "deq")?;
    let t1 = Instant::now();
    let state = Deq::new(mesh, population, domain, config, &[])?;
    let outcome = state.iterate(config, progress)?;
    Ok(MapResult {
        flat_torus: None,
        method: "deq",
        positions: outcome.positions,
        initial: domain.positions.clone(),
        converged: outcome.stop_reason != StopReason::MaxIter,
        stop_reason: outcome.stop_reason,
        iterations: outcome.iterations,
        history: outcome.history,
        time_init: 0.0,
        time_map: t1.elapsed().as_secs_f64(),
        notes: outcome.notes,
    })
}

/// The end of an iteration.
pub(crate) struct Outcome {
    pub positions: Vec<[f64; 3]>,
    pub iterations: usize,
    pub history: Vec<f64>,
    pub stop_reason: StopReason,
    pub notes: Vec<String>,
}

/// The fixed data of one DEQ run: D⁰, its operators, the boundary circles.
pub(crate) struct Deq<'a> {
    pub faces: &'a [[u32; 3]],
    /// D⁰, the initial circle domain: every LBS maps from here.
    pub source: Vec<[f64; 3]>,
    pub source_areas: Vec<f64>,
    pub boundary: CircleBoundary,
    pub flow: DensityFlow<'a>,
    pub incidence: VertexFaces,
    /// Cotangent weights of D⁰ (the β term's Laplacian).
    pub source_weights: Vec<[f64; 3]>,
    pub lbs: LinearBeltramiSolver,
    pub alpha: f64,
    pub beta: f64,
    pub dt: f64,
}

impl<'a> Deq<'a> {
    /// Prepares the run from the circle domain `domain` (vertex images and circles).
    /// `landmarks` (LDEQ) are vertices held fixed by every reconstruction, like the boundary.
    pub fn new(
        mesh: &'a TriMesh,
        population: &'a [f64],
        domain: &CircleDomain,
        config: &Config,
        landmarks: &[usize],
    ) -> Result<Self> {
        let n = mesh.n_vertices();
        let faces = &mesh.faces[..];
        if domain.positions.len() != n || count_nonpositive(&domain.positions, faces) > 0 {
            return Err(Error::Argument(
                "the initial circle domain map must have one point per vertex and no flipped face"
                    .into(),
            ));
        }
        let circles = domain
            .centers
            .iter()
            .zip(&domain.radii)
            .map(|(&center, &radius)| Circle { center, radius })
            .collect();
        let boundary = CircleBoundary::new(n, domain.loops.clone(), circles);
        let source = domain.positions.clone();
        let source_areas = face_areas(&source, faces);
        let source_weights = crate::fem::cotangent_weights(&source, faces);
        let mut fixed = boundary.is_boundary();
        for &v in landmarks {
            fixed[v] = true;
        }
        let lbs = LinearBeltramiSolver::new(n, faces, &fixed)?;
        Ok(Self {
            faces,
            source,
            source_areas,
            boundary,
            flow: DensityFlow::new(n, faces, population)?,
            incidence: VertexFaces::new(n, faces),
            source_weights,
            lbs,
            alpha: config.alpha,
            beta: config.beta,
            dt: config.dt,
        })
    }

    /// The stopping energy: the DEQ energy (5.1) with its density term measured by Var(ρ̃)
    /// (the quantity the paper reports) rather than `∫|∇ρ|²`, plus `α ∫_{D⁰}|ν|²`.
    /// The Dirichlet energy of a piecewise-constant density sampled on triangles grows with
    /// the resolution and with the triangle-to-triangle noise that no map removes, so a fixed
    /// ε would mean different things on different meshes; Var(ρ̃) is dimensionless. The β term
    /// `∫|∇ν|²` is left out of the test: across the jumps of a discontinuous density ν jumps
    /// too, and its discrete gradient changes by more than ε from one iteration to the next
    /// while the map barely moves (measured on the four-quadrant annulus: β∫|∇ν|² ≈ 0.3 ± 0.05).
    pub(crate) fn energy(&self, x: &[[f64; 3]], face_density_var: f64) -> f64 {
        let nu = beltrami_coefficient(&self.source, x, self.faces);
        let e2: f64 = nu
            .iter()
            .zip(&self.source_areas)
            .map(|(z, a)| a * z.norm_sqr())
            .sum();
        face_density_var + self.alpha * e2
    }

    /// The diffusion time of the velocity on the map `x`: `min(δt, 10 Ā, |D|/400)` with Ā the
    /// mean face area and |D| the domain's area — the DEM iteration's bound (`planar_diffusion`,
    /// which allows 30 Ā), tighter: diffusing over more than a ring or two of triangles only
    /// blurs the density, and the velocity then cannot reopen a single squeezed triangle
    /// (measured: with 30 Ā the Var(ρ̃) of alex_3 stalls at 0.12, with 10 Ā it reaches 0.03).
    pub(crate) fn diffusion_time(&self, x: &[[f64; 3]]) -> f64 {
        let area: f64 = face_areas(x, self.faces).iter().sum();
        self.dt
            .min(SMOOTHING_FACES * area / self.faces.len() as f64)
            .min(area * SMOOTHING_AREA)
    }

    /// Algorithm 5.3 from D⁰, with step control: each GM and BDED step starts at the current
    /// step h ≤ δt and is halved while its reconstruction flips a triangle or raises Var(ρ̃);
    /// after an accepted BDED step h doubles again (up to δt). The stop: |E_n − E_{n−1}| < ε
    /// after a full step (tolerance), or Var(ρ̃) improving by less than 2% over 8 iterations
    /// or no acceptable step (stationary).
    pub fn iterate(&self, config: &Config, progress: ProgressFn) -> Result<Outcome> {
        let relax = Relaxation::new(&self.source_weights, &self.incidence, self.faces);
        let terms = HoleTerms::new(
            self.faces,
            &self.source,
            &self.source_areas,
            &self.source_weights,
            &self.incidence,
            &self.boundary,
            self.alpha,
            self.beta,
        );
        let mut boundary = self.boundary.clone();
        let mut x = self.source.clone();
        let mut fit = self.flow.fit(&x);
        let mut var = fit.var;
        let mut energy = self.energy(&x, var);
        let mut history = Vec::new();
        // The best map met (lowest Var(ρ̃)) is the result; the iteration may pass through
        // maps with a higher variance while it lowers the density error.
        let mut best = (var, x.clone());
        let mut best_history = vec![var];
        let mut notes = Vec::new();
        let mut stop_reason = StopReason::MaxIter;
        let mut iterations = 0;
        let mut h = self.dt;
        for it in 1..=config.max_iter {
            iterations = it;
            if config.geometry_update && boundary.loops.len() > 1 {
                let s = self.flow.evaluate(&x, self.diffusion_time(&x))?;
                let nu = beltrami_coefficient(&self.source, &x, self.faces);
                let rates = terms.rates(&x, &nu, &s.velocity, &boundary);
                if let Some(f) =
                    self.modify_geometry(&mut x, &mut boundary, &rates, &nu, &relax, h, fit)?
                {
                    fit = f;
                }
            }
            let s = self.flow.evaluate(&x, self.diffusion_time(&x))?;
            let taken = self.descend(&mut x, &boundary, &s, &relax, h, fit)?;
            let Some((step, f)) = taken else {
                stop_reason = StopReason::Stationary;
                break;
            };
            fit = f;
            var = fit.var;
            let e = self.energy(&x, var);
            history.push(e);
            if var < best.0 {
                best = (var, x.clone());
            }
            best_history.push(best.0);
            progress(Progress {
                iteration: it,
                max_iter: config.max_iter,
                error: var,
            });
            if (e - energy).abs() * self.dt / step < config.epsilon {
                stop_reason = StopReason::Tolerance;
                break;
            }
            energy = e;
            if best_history.len() > STATIONARY_WINDOW
                && best.0
                    > best_history[best_history.len() - 1 - STATIONARY_WINDOW]
                        * (1.0 - STATIONARY_GAIN)
            {
                stop_reason = StopReason::Stationary;
                break;
            }
            h = (2.0 * step).min(self.dt);
        }
        let (var, x) = best;
        if stop_reason == StopReason::Stationary && iterations < config.max_iter {
            notes.push(format!(
                "stopped after {iterations} iterations: the density no longer improved (Var(ρ̃) {var:.4})"
            ));
        }
        Ok(Outcome {
            positions: x,
            iterations,
            history,
            stop_reason,
            notes,
        })
    }

    /// One GM step (Alg. 5.1): move the holes by h × `rates`, rebuild the domain by LBS from
    /// ν relaxed by (5.31)–(5.34). The step is halved while a hole would leave the disk or
    /// touch another, or the rebuilt map flips a triangle or raises the density error above
    /// that of `fit`. Returns the new fit, or `None` (nothing changed) when no step was
    /// acceptable.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn modify_geometry(
        &self,
        x: &mut Vec<[f64; 3]>,
        boundary: &mut CircleBoundary,
        rates: &[super::geometry_modification::HoleRate],
        nu: &[Complex64],
        relax: &Relaxation,
        mut h: f64,
        fit: Fit,
    ) -> Result<Option<Fit>> {
        let margin = 2.0 * mean_boundary_edge(x, &boundary.loops);
        for _ in 0..MAX_HALVINGS {
            let relaxed = relax.apply(nu, nu, h * self.alpha, h * self.beta);
            let circles: Vec<Circle> = std::iter::once(boundary.circles[0])
                .chain(
                    boundary.circles[1..]
                        .iter()
                        .zip(rates)
                        .map(|(c, r)| Circle {
                            center: [c.center[0] + h * r.center[0], c.center[1] + h * r.center[1]],
                            radius: (c.radius + h * r.radius).max(0.5 * c.radius),
                        }),
                )
                .collect();
            if !circles_fit(&circles, margin) {
                h *= 0.5;
                continue;
            }
            let mut target = x.clone();
            for (l, lp) in boundary.loops.iter().enumerate().skip(1) {
                let (old, new) = (boundary.circles[l], circles[l]);
                let (sin, cos) = (h * rates[l - 1].angle).sin_cos();
                for &v in lp {
                    let u = old.radial(x[v as usize]);
                    let u = [cos * u[0] - sin * u[1], sin * u[0] + cos * u[1]];
                    target[v as usize] = [
                        new.center[0] + new.radius * u[0],
                        new.center[1] + new.radius * u[1],
                        0.0,
                    ];
                }
            }
            let y = self.lbs.solve(&self.source, &relaxed, &target)?;
            if count_nonpositive(&y, self.faces) == 0 {
                let f = self.flow.fit(&y);
                if f.var <= fit.var {
                    *x = y;
                    boundary.circles = circles;
                    return Ok(Some(f));
                }
            }
            h *= 0.5;
        }
        Ok(None)
    }

    /// One BDED step (Alg. 5.2) with the velocity of `s`, starting at step `h` and halved
    /// while the move or its reconstruction flips a triangle or does not lower the density
    /// error of `fit`. Returns the step taken and the new fit, or `None` when no step was
    /// acceptable.
    pub(crate) fn descend(
        &self,
        x: &mut Vec<[f64; 3]>,
        boundary: &CircleBoundary,
        s: &FlowState,
        relax: &Relaxation,
        mut h: f64,
        fit: Fit,
    ) -> Result<Option<(f64, Fit)>> {
        let nu0 = beltrami_coefficient(&self.source, x, self.faces);
        let mut velocity = s.velocity.clone();
        boundary.neumann_layer(x, &mut velocity, self.diffusion_time(x).sqrt());
        let moved = |h: f64| {
            let mut y: Vec<[f64; 3]> = x
                .iter()
                .zip(&velocity)
                .map(|(p, v)| [p[0] + h * v[0], p[1] + h * v[1], 0.0])
                .collect();
            // Boundary vertices: the tangential part only, back onto their circles.
            for lp in &boundary.loops {
                for &v in lp {
                    y[v as usize] = x[v as usize];
                }
            }
            slide_boundary(&mut y, &velocity, h, boundary);
            y
        };
        for _ in 0..MAX_HALVINGS {
            let y = self.limit_squeeze(x, moved(h), boundary);
            // A move that flips a triangle would leave it to the cut-off (5.43), which rebuilds
            // it almost flat; a shorter move is taken instead.
            if count_nonpositive(&y, self.faces) > 0 {
                h *= 0.5;
                continue;
            }
            let predicted = beltrami_coefficient(&self.source, &y, self.faces);
            let nu = relax.apply(&predicted, &nu0, h * self.alpha, h * self.beta);
            let z = self.lbs.solve(&self.source, &nu, &y)?;
            let flips = count_nonpositive(&z, self.faces);
            let f = self.flow.fit(&z);
            if flips == 0 && fit.improved_by(&f) {
                *x = z;
                return Ok(Some((h, f)));
            }
            h *= 0.5;
        }
        Ok(None)
    }
}

impl Deq<'_> {
    /// Shortens the move `x → y` vertex by vertex so that no triangle moving linearly would
    /// lose more than about half its area: every triangle whose collapse time `t` along the
    /// move is below 2 limits its corners' moves to the fraction `t/2` (the DEM iteration's
    /// margin, `planar_diffusion::safe_update`, applied locally: one squeezed triangle at the
    /// rim of a hole must not stop the whole domain). Boundary vertices stay on their circles.
    /// Beyond the margin the move's Beltrami coefficient would be cut off (5.43) and the
    /// reconstruction would squeeze triangles almost flat.
    pub(crate) fn limit_squeeze(
        &self,
        x: &[[f64; 3]],
        mut y: Vec<[f64; 3]>,
        boundary: &CircleBoundary,
    ) -> Vec<[f64; 3]> {
        use rayon::prelude::*;
        let t: Vec<f64> = self
            .faces
            .par_iter()
            .map(|f| {
                let p = f.map(|v| x[v as usize]);
                let d = f.map(|v| {
                    let (a, b) = (x[v as usize], y[v as usize]);
                    [b[0] - a[0], b[1] - a[1]]
                });
                super::planar_diffusion::collapse_time(p, d)
            })
            .collect();
        let mut factor = vec![1.0f64; x.len()];
        for (f, &tf) in self.faces.iter().zip(&t) {
            if tf < 2.0 {
                for &v in f {
                    factor[v as usize] = factor[v as usize].min(0.5 * tf);
                }
            }
        }
        for (v, p) in y.iter_mut().enumerate() {
            let k = factor[v];
            if k < 1.0 {
                let a = x[v];
                *p = [a[0] + k * (p[0] - a[0]), a[1] + k * (p[1] - a[1]), 0.0];
                let l = boundary.loop_of[v];
                if l != u32::MAX {
                    *p = boundary.circles[l as usize].project(*p);
                }
            }
        }
        y
    }
}

/// Mean edge length along the boundary loops.
fn mean_boundary_edge(x: &[[f64; 3]], loops: &[Vec<u32>]) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for lp in loops {
        for i in 0..lp.len() {
            let (a, b) = (x[lp[i] as usize], x[lp[(i + 1) % lp.len()] as usize]);
            s += (a[0] - b[0]).hypot(a[1] - b[1]);
            n += 1;
        }
    }
    s / n.max(1) as f64
}

/// True when every hole lies inside the unit circle and outside the others, with `margin`.
fn circles_fit(circles: &[Circle], margin: f64) -> bool {
    let holes = &circles[1..];
    holes.iter().enumerate().all(|(i, a)| {
        a.radius > 0.0
            && a.center[0].hypot(a.center[1]) + a.radius <= 1.0 - margin
            && holes[..i].iter().all(|b| {
                (a.center[0] - b.center[0]).hypot(a.center[1] - b.center[1])
                    >= a.radius + b.radius + margin
            })
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::generate::annulus;

    /// A planar annulus is already a circle domain: D⁰ is the input scaled to the unit disk.
    pub(crate) fn annulus_domain(mesh: &TriMesh, inner: f64) -> CircleDomain {
        let topo = topology(mesh);
        let mut loops = topo.boundary_loops.clone();
        let r0 = |l: &Vec<u32>| {
            let p = mesh.positions[l[0] as usize];
            p[0].hypot(p[1])
        };
        loops.sort_by(|a, b| r0(b).total_cmp(&r0(a)));
        let mut positions = mesh.positions.clone();
        let outer = r0(&loops[0]);
        for p in positions.iter_mut() {
            *p = [p[0] / outer, p[1] / outer, 0.0];
        }
        CircleDomain {
            positions,
            loops,
            centers: vec![[0.0, 0.0], [0.0, 0.0]],
            radii: vec![1.0, inner / outer],
        }
    }

    pub(crate) fn quadrant_population(mesh: &TriMesh) -> Vec<f64> {
        let areas = face_areas(&mesh.positions, &mesh.faces);
        mesh.faces
            .iter()
            .zip(&areas)
            .map(|(f, a)| {
                let c = f.iter().fold([0.0; 2], |s, &v| {
                    let p = mesh.positions[v as usize];
                    [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]
                });
                a * match (c[0] > 0.0, c[1] > 0.0) {
                    (true, true) => 4.0,
                    (false, true) => 1.0,
                    (false, false) => 2.0,
                    (true, false) => 3.0,
                }
            })
            .collect()
    }

    #[test]
    fn annulus_with_four_quadrants_equalizes_bijectively() {
        let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
        let pop = quadrant_population(&mesh);
        // As `initial_circle_domain` does: the disk automorphism that balances the areas.
        let domain = balance_areas(&annulus_domain(&mesh, 0.4), &mesh.faces, &pop);
        let r = run_from(&mesh, &pop, &domain, &Config::default(), &mut |_| {}).unwrap();
        let m = crate::metrics::compute(
            &mesh,
            &pop,
            &r.initial,
            &r.positions,
            crate::metrics::Domain::Plane,
            None,
        );
        assert_eq!(m.flipped_triangles, 0);
        assert!(r.converged);
        assert!(
            m.face_density_var_final < 0.10,
            "{}",
            m.face_density_var_final
        );
        assert!(m.mean_abs_mu < 0.2);
    }
}
