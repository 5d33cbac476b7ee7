//! EDEQ: ellipsoidal density-equalizing quasi-conformal maps, the ellipsoid's radii chosen with
//! the map (Lyu, Lui & Choi, "Ellipsoidal density-equalizing map for genus-0 closed surfaces",
//! 2026, §4).
//!
//! The radius `a` along x stays at the initial guess's (it sets the size); `b` and `c` are
//! chosen to minimise the paper's energy of the map `f` onto the ellipsoid,
//!
//! E(a, b, c) = Σ_v |∇ρ̃(v) / max ρ_V|² + α Σ_T |μ_T|²,
//!
//! ρ̃ the density after one diffusion step of length 0.1 on the map (the paper's δt), its
//! gradient averaged to the vertices (W^FV), and μ the Beltrami coefficient of the map from
//! the input surface. A candidate ellipsoid carries the map by `diag(a, b', c')
//! diag(a, b, c)⁻¹`, as in the paper, so its image on the unit sphere is kept.
//!
//! The paper interleaves the flow with a search over a 3 × 3 grid of (b, c) every few
//! iterations, judging each candidate by the current map carried onto it. Here the energy of
//! the equalized maps themselves is lowered, by a descent over the radii: EDEM's iteration
//! ([`super::edem`], without the local area matching, which lowers no term of E) runs on the
//! guess; the radii minimising E for that map carried onto them (Nelder–Mead over log b,
//! log c) give the direction and length of a step; the flow runs again from the ellipsoidal
//! conformal map onto the new radii, and the step is kept when the new map's energy is lower,
//! else halved. The search ends when a step of less than [`RADII_TOL`] is proposed or none
//! lowers the energy; the map of lowest energy is returned, equalized on its radii.

use super::density::SphereDiffusion;
use super::edem::InitialMaps;
use super::input::SphereInput;
use super::sdem::{self, Target, equalize};
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::{cross, dot, local_frame};
use crate::linalg::VertexOrder;
use crate::methods::MethodConfig;
use crate::methods::{MapResult, Progress, ProgressFn, StopReason};
use crate::qc::beltrami_coefficient_from_frames;
use crate::{Error, Result, TriMesh};
use std::time::Instant;

/// EDEQ parameters; `Default` gives the paper's defaults (α = 5) and a guess of the radii from
/// the surface's extents.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The initial guess of the ellipsoid; `None` takes radii proportional to the surface's
    /// spread along x, y and z ([`guess_from_extents`]).
    pub guess: Option<Ellipsoid>,
    /// The weight α of the distortion against the density in the energy (paper: 5).
    pub alpha: f64,
    /// Each flow's stop, iteration limit and time step, as EDEM's ([`super::edem::FLOW`]).
    pub flow: sdem::Config,
    /// The most maps computed (each a flow on one set of radii; module docs).
    pub rounds: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            guess: None,
            alpha: 5.0,
            flow: super::edem::FLOW,
            rounds: 20,
        }
    }
}

/// The search stops when the radii would change by less than this share.
pub const RADII_TOL: f64 = 1e-3;

/// The paper's diffusion time δt in the energy's density term.
const ENERGY_DT: f64 = 0.1;

/// Nelder–Mead steps per radii search.
const SEARCH_STEPS: usize = 80;

/// A radii search ends when its simplex spans less than this in log b and log c: a tenth of
/// the least change of the radii the descent takes ([`RADII_TOL`]).
const SEARCH_TOL: f64 = 0.1 * RADII_TOL;

impl MethodConfig for Config {
    /// Computes the EDEQ of `mesh` (a genus-0 closed surface) with one `population` value per face.
    /// The result lies on the ellipsoid it chose ([`MapResult::ellipsoid`]), in input vertex order.
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        let t0 = Instant::now();
        let input = SphereInput::new(mesh, population, &self.flow, "edeq")?;
        if !(self.alpha.is_finite() && self.alpha >= 0.0) {
            return Err(Error::Argument(format!(
                "edeq's alpha must be a finite number ≥ 0, got {}",
                self.alpha
            )));
        }
        let guess = match self.guess {
            Some(g) => g,
            None => guess_from_extents(mesh)?,
        };
        let k = guess.normalizing_exponent();
        let domain = guess.scaled_by_power_of_two(k);
        let (local, mesh, population, order) = input.parts();
        let mut notes = Vec::new();
        let mut initial_maps = InitialMaps::new(mesh, population, order);
        let initial = initial_maps.onto(&guess, &domain, &mut notes)?;
        let time_init = t0.elapsed().as_secs_f64();
        let energy = Energy::new(mesh, population, order, self.alpha)?;
        let e_initial = energy.of(&initial)?.total(self.alpha);

        let mut iterations = 0;
        let mut history = Vec::new();
        let mut flow = |domain: Ellipsoid, start: Vec<[f64; 3]>| -> Result<Trial> {
            let on = Target {
                domain,
                method: "edeq",
                match_areas: false,
            };
            let done = iterations;
            let mut counted = |p: Progress| {
                progress(Progress {
                    iteration: p.iteration + done,
                    max_iter: p.max_iter + done,
                    error: p.error,
                })
            };
            let out = equalize(
                on,
                mesh,
                population,
                start,
                Some(order),
                &self.flow,
                &mut counted,
            )?;
            iterations += out.iterations;
            history.extend_from_slice(&out.history);
            let terms = energy.of(&out.positions)?;
            Ok(Trial {
                domain,
                energy: terms.total(self.alpha),
                terms,
                result: out,
            })
        };
        let mut best = flow(domain, initial.clone())?;
        let mut rounds = 1;
        let mut stretch = 1.0;
        let mut settled = false;
        while rounds < self.rounds && best.result.converged {
            let proposed = best_radii(&energy, &best.domain, &best.result.positions)?;
            let step = log_step(&best.domain, &proposed);
            let mut better = None;
            let mut f = stretch;
            while f * max_abs(step) > RADII_TOL && f >= MIN_STRETCH {
                let domain = along(&best.domain, step, f)?;
                // A fresh start on the new radii: the ellipsoidal conformal map onto them (a map
                // carried over would keep the distortion of the flows before).
                let mut ignored = Vec::new();
                let start =
                    initial_maps.onto(&domain.scaled_by_power_of_two(-k), &domain, &mut ignored)?;
                let trial = flow(domain, start)?;
                rounds += 1;
                if trial.result.converged && trial.energy < best.energy {
                    better = Some(trial);
                    break;
                }
                f *= 0.5;
                if rounds >= self.rounds {
                    break;
                }
            }
            match better {
                Some(t) => {
                    let full = f >= stretch;
                    best = t;
                    stretch = if full {
                        (2.0 * stretch).min(MAX_STRETCH)
                    } else {
                        f
                    };
                }
                None => {
                    settled = true;
                    break;
                }
            }
        }
        let Trial {
            domain,
            energy: e_final,
            terms,
            mut result,
        } = best;
        result.iterations = iterations;
        result.history = history;
        let chosen = domain.scaled_by_power_of_two(-k);
        let [a, b, c] = chosen.radii();
        notes.push(format!(
            "radii {a:.6}:{b:.6}:{c:.6} chosen after {rounds} maps; energy {e_final:.6e} (density \
         {:.3e}, distortion Σ|μ|² {:.6e}, α = {}); the initial map's {e_initial:.6e}",
            terms.density, terms.distortion, self.alpha
        ));
        if !settled && result.converged {
            result.converged = false;
            result.stop_reason = StopReason::MaxIter;
            notes.push(format!(
                "the radii were still improving the energy after {rounds} maps (the limit)"
            ));
        }
        let unscale = |x: &[[f64; 3]]| -> Vec<[f64; 3]> {
            let mut x = local.restore_vertices(x);
            crate::mesh::scale::scale_positions(&mut x, -k);
            x
        };
        result.method = "edeq";
        result.positions = unscale(&result.positions);
        result.initial = unscale(&initial);
        result.ellipsoid = Some(chosen);
        result.time_init = time_init;
        notes.append(&mut result.notes);
        result.notes = notes;
        Ok(result)
    }
}

/// The guess of the radii from the surface: proportional to the standard deviations along x,
/// y and z of the solid it encloses (moments by the divergence theorem, one tetrahedron from
/// the origin per face), with a = 1. A solid ellipsoid's are its radii over √5, so an
/// ellipsoid's surface gets its own proportions.
pub fn guess_from_extents(mesh: &TriMesh) -> Result<Ellipsoid> {
    let (mut volume, mut first, mut second) = (0.0, [0.0; 3], [0.0; 3]);
    for f in &mesh.faces {
        let [p, q, r] = f.map(|v| mesh.positions[v as usize]);
        let v = dot(p, cross(q, r)) / 6.0;
        volume += v;
        for d in 0..3 {
            let sum = p[d] + q[d] + r[d];
            first[d] += v * sum / 4.0;
            second[d] += v * (p[d] * p[d] + q[d] * q[d] + r[d] * r[d] + sum * sum) / 20.0;
        }
    }
    let s: [f64; 3] =
        std::array::from_fn(|d| (second[d] / volume - (first[d] / volume).powi(2)).sqrt());
    Ellipsoid::new(1.0, s[1] / s[0], s[2] / s[0]).map_err(|e| {
        Error::Argument(format!(
            "the surface's extents give no ellipsoid to start from ({e}); give the initial guess"
        ))
    })
}

/// The change from `from` to `to` in log b and log c.
fn log_step(from: &Ellipsoid, to: &Ellipsoid) -> [f64; 2] {
    let (f, t) = (from.radii(), to.radii());
    [(t[1] / f[1]).ln(), (t[2] / f[2]).ln()]
}

/// The largest |component| of a step.
fn max_abs(step: [f64; 2]) -> f64 {
    step[0].abs().max(step[1].abs())
}

/// `domain` with b and c moved by `f · step` in log b, log c.
fn along(domain: &Ellipsoid, step: [f64; 2], f: f64) -> Result<Ellipsoid> {
    let [a, b, c] = domain.radii();
    Ellipsoid::new(a, b * (f * step[0]).exp(), c * (f * step[1]).exp())
}

/// A map equalized on some radii, with its energy.
struct Trial {
    domain: Ellipsoid,
    energy: f64,
    terms: Terms,
    result: MapResult,
}

/// The first try along a proposed change of the radii goes this many times its length at most
/// (after rounds whose full tries were kept: the proposals fall short of the optimum, by a
/// share that stays about the same from one round to the next) ...
const MAX_STRETCH: f64 = 4.0;

/// ... and a change is given up once halved below this share.
const MIN_STRETCH: f64 = 0.25;

/// The map `x` on `from` carried onto `to` by `diag(to) diag(from)⁻¹` (its image on the unit
/// sphere kept).
fn carry(x: &[[f64; 3]], from: &Ellipsoid, to: &Ellipsoid) -> Vec<[f64; 3]> {
    x.iter()
        .map(|&p| to.project(to.from_sphere(from.to_sphere(p))))
        .collect()
}

/// The radii (a kept) minimising the energy of the map `x` on `domain` carried onto them.
fn best_radii(energy: &Energy, domain: &Ellipsoid, x: &[[f64; 3]]) -> Result<Ellipsoid> {
    let [a, b, c] = domain.radii();
    let at = |s: [f64; 2]| Ellipsoid::new(a, b * s[0].exp(), c * s[1].exp());
    let cost = |s: [f64; 2]| -> f64 {
        match at(s) {
            Ok(e) => energy
                .of(&carry(x, domain, &e))
                .map_or(f64::INFINITY, |v| v.total(energy.alpha)),
            Err(_) => f64::INFINITY,
        }
    };
    let (s, value) = crate::optimize::nelder_mead(cost, [0.0, 0.0], 0.05, SEARCH_STEPS, SEARCH_TOL);
    if value.is_finite() && value < cost([0.0, 0.0]) {
        at(s)
    } else {
        Ok(*domain)
    }
}

/// The two terms of the energy of a map (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Terms {
    /// Σ_v |∇ρ̃(v) / max ρ_V|².
    pub density: f64,
    /// Σ_T |μ_T|².
    pub distortion: f64,
}

impl Terms {
    /// `density + alpha · distortion`.
    pub fn total(&self, alpha: f64) -> f64 {
        self.density + alpha * self.distortion
    }
}

/// The energy of maps of one mesh (module docs), with its diffusion operator.
pub(crate) struct Energy<'a> {
    mesh: &'a TriMesh,
    /// The input's faces in their own frames ([`local_frame`]), for μ.
    frames: Vec<[[f64; 2]; 3]>,
    diffusion: SphereDiffusion<'a>,
    alpha: f64,
}

impl<'a> Energy<'a> {
    fn new(
        mesh: &'a TriMesh,
        population: &'a [f64],
        order: &VertexOrder,
        alpha: f64,
    ) -> Result<Self> {
        let frames = mesh
            .faces
            .iter()
            .map(|f| local_frame(f.map(|v| mesh.positions[v as usize])))
            .collect();
        Ok(Self {
            mesh,
            frames,
            diffusion: SphereDiffusion::new(
                Ellipsoid::UNIT_SPHERE,
                mesh.n_vertices(),
                &mesh.faces,
                population,
                Some(order),
            )?,
            alpha,
        })
    }

    /// The terms of the map `x` (on any ellipsoid): μ is computed on a second thread beside
    /// the diffusion solve.
    pub(crate) fn of(&self, x: &[[f64; 3]]) -> Result<Terms> {
        let d = self.diffusion.measure(x);
        let (frames, faces) = (&self.frames, &self.mesh.faces);
        let (grad, distortion) = std::thread::scope(|s| {
            let mu = s.spawn(|| {
                beltrami_coefficient_from_frames(frames, x, faces)
                    .iter()
                    .map(|m| m.norm_sqr())
                    .sum::<f64>()
            });
            let grad = self.diffusion.diffused_gradient(x, &d, ENERGY_DT);
            (grad, mu.join())
        });
        let (_, grad) = grad?;
        let distortion = distortion
            .map_err(|_| Error::Numerical("the Beltrami coefficient's thread failed".into()))?;
        let top = d.rho_v.iter().fold(0.0f64, |m, &r| m.max(r));
        let density = if top > 0.0 {
            grad.iter()
                .map(|g| (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) / (top * top))
                .sum()
        } else {
            0.0
        };
        Ok(Terms {
            density,
            distortion,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;
    use crate::metrics::{Domain, compute};

    #[test]
    fn a_stretched_sphere_gets_radii_near_its_own() {
        // An icosphere stretched to 1:1.3:1.8, mapped by area from the guess 1:1:1: the least
        // distorted ellipsoid is its own shape, so the radii move towards it.
        let mut mesh = icosphere(4).unwrap();
        let shape = Ellipsoid::new(1.0, 1.3, 1.8).unwrap();
        for p in mesh.positions.iter_mut() {
            *p = shape.from_sphere(*p);
        }
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let config = Config {
            guess: Some(Ellipsoid::UNIT_SPHERE),
            ..Config::default()
        };
        let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
        let e = r.ellipsoid.unwrap();
        let [a, b, c] = e.radii();
        assert_eq!(a, 1.0);
        assert!(
            (b - 1.3).abs() < 0.1 && (c - 1.8).abs() < 0.15,
            "{a}:{b}:{c}"
        );
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(m.mean_abs_mu < 0.05, "{m:?}");
        assert!(m.density_error_mean < 0.02, "{m:?}");
        for p in &r.positions {
            assert!(e.residual(*p) < 1e-12);
        }
    }

    #[test]
    fn the_guess_follows_the_extents() {
        let mut mesh = icosphere(3).unwrap();
        let shape = Ellipsoid::new(2.0, 1.0, 3.0).unwrap();
        for p in mesh.positions.iter_mut() {
            *p = shape.from_sphere(*p);
        }
        let g = guess_from_extents(&mesh).unwrap().radii();
        assert!(
            (g[1] - 0.5).abs() < 0.05 && (g[2] - 1.5).abs() < 0.1,
            "{g:?}"
        );
    }

    #[test]
    fn a_negative_alpha_is_refused() {
        let mesh = icosphere(2).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let config = Config {
            alpha: -1.0,
            ..Config::default()
        };
        assert!(matches!(
            config.run(&mesh, &pop, &mut |_| {}),
            Err(Error::Argument(_))
        ));
    }
}
