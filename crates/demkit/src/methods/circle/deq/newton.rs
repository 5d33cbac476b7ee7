//! The DEQ energy ([`super::energy`]) minimised over circle domain maps
//! ([`super::parameters`]) by projected Newton: each step solves with the per-face Hessians
//! (positive semi-definite, so the step descends), the circle parameterization to first order
//! and Levenberg–Marquardt damping, by one sparse Cholesky factorization of a pattern analysed
//! once. The step is shortened while it would fold a triangle or fail to lower the energy
//! (the density misfit is a barrier against collapse), so every map met is bijective; when a
//! few faces about to collapse cut it short, the step with the vertices around them held is
//! tried too, so that they do not hold back the whole map.
//!
//! The minimisation is a flow of the density-equalizing iteration every method runs
//! ([`crate::methods::iteration`]): one Newton step is one advance, the energy is the merit,
//! and the iteration stops on the energy's decrease (`docs/deviations.md`, the shared
//! iteration).

use super::energy::{self, Face, Misfit};
use super::parameters::Parameters;
use crate::Result;
use crate::fem::VertexFaces;
use crate::geometry::face_areas;
use crate::linalg::{ElementPattern, SparseCholesky, packed_index};
use crate::mesh::topology::{ring_distances, vertex_neighbours};
use crate::methods::disk::planar_diffusion::collapse_time;
use crate::methods::iteration::{Flow, Keep, Measured, Moved, Rules, Stationary, Step, iterate};
use crate::methods::{ProgressFn, StopReason};
use crate::metrics::normalized_variance;
use rayon::prelude::*;

/// The smallest and largest Levenberg–Marquardt damping, as a fraction of the Hessian's mean
/// diagonal.
const MIN_DAMPING: f64 = 1e-8;
const MAX_DAMPING: f64 = 1e4;

/// How many chord steps may follow a factorization (docs/deviations.md, DEQ: chord steps).
const REUSE: usize = 2;

/// The energy falling by less than the tolerance (relative) over this many steps is a
/// minimum, whatever the Newton decrement says ([`Stationary::Decrease`]).
const STALL_ITERATIONS: usize = 5;

/// An energy this small (a mean of squared relative quantities: densities equal to about
/// 1e-10) is a minimum; relative decrements of it are rounding noise.
const NEGLIGIBLE_ENERGY: f64 = 1e-20;

/// A face's energy gradient and Hessian in its corners' coordinates (x₀, y₀, x₁, …).
type CornerDerivatives = ([f64; 6], [[f64; 6]; 6]);

/// What the minimisation works on.
pub(crate) struct Problem<'a> {
    /// The surface (the map's numbering: its vertices, then the hole fillings' points).
    pub surface: &'a [[f64; 3]],
    /// The faces whose energy is minimised, and their populations.
    pub faces: &'a [[u32; 3]],
    pub population: &'a [f64],
    /// The outer loop and the holes' loops.
    pub outer: &'a [u32],
    pub holes: &'a [Vec<u32>],
    /// Vertices that do not move.
    pub pinned: &'a [u32],
    /// The holes keep their circles (their vertices still slide along them).
    pub fixed_holes: bool,
    /// The weight α of the distortion term.
    pub alpha: f64,
    pub misfit: Misfit,
    /// Newton iterations at most.
    pub max_iterations: usize,
    /// Stop when the Newton decrement, or the decrease over the last [`STALL_ITERATIONS`]
    /// steps, is below this fraction of the energy.
    pub tolerance: f64,
}

/// How a minimisation ended.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Outcome {
    /// Newton iterations done.
    pub iterations: usize,
    /// sd/mean of the vertex density after every iteration ([`density_spread`]): the quantity
    /// the density-equalizing iteration records, so that DEQ's history and progress are one
    /// quantity through every stage.
    pub history: Vec<f64>,
    /// True when the Newton decrement of a fresh, undamped Hessian fell below the tolerance
    /// (a damped one understates it: brain with six holes stopped at Var(ρ̃) 0.13 instead of
    /// 0.008), the energy fell by less than the tolerance over [`STALL_ITERATIONS`] steps, or
    /// no step could lower the energy at all (a minimum); false when the iteration limit ran
    /// out first.
    pub converged: bool,
}

/// sd/mean of the vertex density of the map `x` over the problem's faces: `P / A` of every face
/// averaged at its vertices by the plain Whitney average (4.27), as the density-equalizing
/// iteration measures it (`planar_diffusion`); vertices of no face are left out.
pub(crate) fn density_spread(p: &Problem, incidence: &VertexFaces, x: &[[f64; 3]]) -> f64 {
    let areas = face_areas(x, p.faces);
    let rho_f: Vec<f64> = p
        .population
        .iter()
        .zip(&areas)
        .map(|(q, a)| q / a)
        .collect();
    let rho_v: Vec<f64> = incidence
        .average(&rho_f)
        .into_iter()
        .enumerate()
        .filter(|&(v, _)| !incidence.faces_of(v).is_empty())
        .map(|(_, r)| r)
        .collect();
    normalized_variance(&rho_v).sqrt()
}

/// Every face's relative area target `Â/A_src` in the map `x`: its share of the population, of
/// the faces' total area in `x`, over its area on the surface.
fn face_targets(p: &Problem, faces: &[Face], total_population: f64, x: &[[f64; 3]]) -> Vec<f64> {
    let total: f64 = p
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| x[v as usize]);
            crate::geometry::signed_area_2d(a, b, c)
        })
        .sum();
    faces
        .iter()
        .zip(p.population)
        .map(|(face, pop)| pop / total_population * total / face.source_area)
        .collect()
}

/// The mean energy of the faces with relative area targets `target` in the map `x`; `None`
/// when `x` folds one of them.
fn mean_energy(p: &Problem, faces: &[Face], target: &[f64], x: &[[f64; 3]]) -> Option<f64> {
    p.faces
        .par_iter()
        .zip(faces.par_iter().zip(target.par_iter()))
        .map(|(f, (face, &k))| {
            let w = f.map(|v| [x[v as usize][0], x[v as usize][1]]);
            energy::value(face, w, k, p.alpha, p.misfit)
        })
        // Summed in face order: the same result whatever the threads.
        .collect::<Vec<Option<f64>>>()
        .into_iter()
        .sum::<Option<f64>>()
        .map(|e| e / p.faces.len().max(1) as f64)
}

/// The problem's energy at the map `x`; `None` when `x` folds a face.
pub(crate) fn energy_at(p: &Problem, x: &[[f64; 3]]) -> Option<f64> {
    let faces: Vec<Face> = p
        .faces
        .iter()
        .map(|f| Face::new(f.map(|v| p.surface[v as usize])))
        .collect();
    let total_population: f64 = p.population.iter().sum();
    mean_energy(p, &faces, &face_targets(p, &faces, total_population, x), x)
}

/// Rings of vertices held around the faces that block a full step, for the partial step.
const HELD_RINGS: usize = 2;

/// The line search starts at this fraction of the first collapse time along the step.
const COLLAPSE_MARGIN: f64 = 0.9;

/// The motion of face `f`'s corners in the image when the unknowns `u` move by `step`.
fn image_motion(params: &Parameters, u: &[f64], f: &[u32; 3], step: &[f64]) -> [[f64; 2]; 3] {
    f.map(|v| {
        let j = params.jacobian(v as usize, u);
        (0..j.count).fold([0.0; 2], |acc, s| {
            let dv = j.derivatives[s];
            [
                acc[0] + dv[0] * step[j.unknowns[s]],
                acc[1] + dv[1] * step[j.unknowns[s]],
            ]
        })
    })
}

/// Every face's collapse time along `step` from the map `x` (unknowns `u`): the step length
/// at which it would first have zero area, to first order (infinite if never).
fn collapse_times(
    p: &Problem,
    params: &Parameters,
    u: &[f64],
    x: &[[f64; 3]],
    step: &[f64],
) -> Vec<f64> {
    p.faces
        .par_iter()
        .map(|f| collapse_time(f.map(|v| x[v as usize]), image_motion(params, u, f, step)))
        .collect()
}

/// A step the line search accepted.
struct Accepted {
    unknowns: Vec<f64>,
    energy: f64,
    /// Its length, as a fraction of the Newton step.
    length: f64,
}

/// Backtracking from `min(1, COLLAPSE_MARGIN · t_collapse)` along `step` (slope `slope`) until the energy
/// (`evaluate`, `None` for a folded map) of the moved unknowns meets Armijo's condition;
/// `None` when 40 halvings do not.
fn line_search(
    params: &Parameters,
    u: &[f64],
    step: &[f64],
    slope: f64,
    t_collapse: f64,
    current: f64,
    evaluate: &mut dyn FnMut(&[f64]) -> Option<f64>,
) -> Option<Accepted> {
    let mut t = (COLLAPSE_MARGIN * t_collapse).min(1.0);
    let mut un = u.to_vec();
    for _ in 0..40 {
        for ((a, &b), s) in un.iter_mut().zip(u).zip(step) {
            *a = b + t * s;
        }
        if params.radii_positive(&un)
            && let Some(e) = evaluate(&un)
            && e <= current + 1e-4 * t * slope
        {
            return Some(Accepted {
                unknowns: un,
                energy: e,
                length: t,
            });
        }
        t *= 0.5;
    }
    None
}

/// A circle domain map as Newton moves it: the positions and the unknowns they are written
/// from ([`Parameters`]; reading the unknowns back from the positions would round them).
#[derive(Clone)]
struct CircleMap {
    x: Vec<[f64; 3]>,
    u: Vec<f64>,
}

/// What [`Newton::measure`] hands to [`Newton::advance`].
struct Energy {
    /// Every face's relative area target in the map ([`face_targets`]).
    target: Vec<f64>,
    /// sd/mean of the vertex density ([`density_spread`]): what the history records.
    spread: f64,
}

/// Projected Newton on the DEQ energy (model (4.2) in its per-face form, in place of
/// Algorithm 5.2's Beltrami descent) as a flow of the density-equalizing iteration
/// ([`iterate`]): the merit is the energy, the stopping quantity the decrease Newton's method
/// can still make, and one advance is one Newton step with its line search. The flow keeps
/// the factorization, its age (chord steps) and the Levenberg–Marquardt damping from one step
/// to the next.
struct Newton<'p, 'a> {
    p: &'p Problem<'a>,
    params: Parameters,
    /// The faces on the surface, and their total population.
    faces: Vec<Face>,
    total_population: f64,
    /// For each face, each corner's unknowns' places in the face's element of the Hessian.
    places: Vec<[[u8; 4]; 3]>,
    pattern: ElementPattern,
    solver: SparseCholesky,
    incidence: VertexFaces,
    /// Built the first time a step is blocked (many minimisations never need it).
    neighbours: std::cell::OnceCell<Vec<Vec<u32>>>,
    element_values: Vec<f64>,
    values: Vec<f64>,
    grad: Vec<f64>,
    damping: f64,
    /// Steps since the last factorization: after a full step the factorization serves again
    /// (a chord step with the new gradient), up to [`REUSE`] times.
    stale: usize,
    /// The decrease an advance that left the map as it was found possible there (the Newton
    /// decrement of a fresh, undamped Hessian; 0 when no step lowers the energy): the next
    /// measurement's stopping quantity. Unknown (infinite) after a move.
    decrease: Option<f64>,
    /// The energy the line search accepted, for a moved map whose retargeted energy cannot be
    /// evaluated.
    accepted: Option<f64>,
}

impl<'p, 'a> Newton<'p, 'a> {
    /// The flow of the problem `p` from the map `x`, and that map with its unknowns.
    fn new(p: &'p Problem<'a>, x: &[[f64; 3]]) -> Result<(Self, CircleMap)> {
        let params = Parameters::new(x.len(), p.faces, p.outer, p.holes, p.pinned, p.fixed_holes);
        let faces: Vec<Face> = p
            .faces
            .iter()
            .map(|f| Face::new(f.map(|v| p.surface[v as usize])))
            .collect();
        let u = params.read(x, p.holes);
        // The unknowns of every face (its element of the Hessian) and, for each corner's
        // unknowns, their places in that list.
        let mut elements: Vec<Vec<u32>> = Vec::with_capacity(p.faces.len());
        let mut places: Vec<[[u8; 4]; 3]> = Vec::with_capacity(p.faces.len());
        for f in p.faces {
            let mut list: Vec<u32> = Vec::with_capacity(8);
            let mut place = [[0u8; 4]; 3];
            for (c, &v) in f.iter().enumerate() {
                let j = params.jacobian(v as usize, &u);
                for (s, &k) in j.unknowns[..j.count].iter().enumerate() {
                    let k = k as u32;
                    place[c][s] = match list.iter().position(|&e| e == k) {
                        Some(at) => at as u8,
                        None => {
                            list.push(k);
                            (list.len() - 1) as u8
                        }
                    };
                }
            }
            elements.push(list);
            places.push(place);
        }
        let pattern = ElementPattern::new(params.n, elements.iter().map(|e| e.as_slice()))?;
        let solver = SparseCholesky::for_pattern(&pattern)?;
        let flow = Self {
            p,
            total_population: p.population.iter().sum(),
            faces,
            places,
            solver,
            incidence: VertexFaces::new(x.len(), p.faces),
            neighbours: std::cell::OnceCell::new(),
            element_values: vec![0.0; pattern.n_element_values()],
            values: vec![0.0; pattern.nnz()],
            grad: vec![0.0; params.n],
            pattern,
            params,
            damping: MIN_DAMPING,
            stale: usize::MAX,
            decrease: None,
            accepted: None,
        };
        Ok((flow, CircleMap { x: x.to_vec(), u }))
    }

    /// Assembles the Hessian of the energy in the unknowns (`corner`: every face's
    /// derivatives in its corners' coordinates) into `self.element_values`.
    // The corners' unknowns index several parallel arrays at once.
    #[allow(clippy::needless_range_loop)]
    fn assemble_elements(&mut self, u: &[f64], corner: &[Option<CornerDerivatives>]) {
        let m = self.p.faces.len() as f64;
        let slices = self.pattern.element_slices(&mut self.element_values);
        let params = &self.params;
        slices
            .into_par_iter()
            .zip(self.p.faces.par_iter().zip(corner.par_iter()))
            .zip(self.places.par_iter())
            .for_each(|((slot, (f, cd)), place)| {
                slot.fill(0.0);
                let Some((_, hc)) = cd else { return };
                let jac: [_; 3] = std::array::from_fn(|k| params.jacobian(f[k] as usize, u));
                for (ca, ja) in jac.iter().enumerate() {
                    for s in 0..ja.count {
                        let la = place[ca][s] as usize;
                        let da = ja.derivatives[s];
                        for (cb, jb) in jac.iter().enumerate() {
                            for t in 0..jb.count {
                                let lb = place[cb][t] as usize;
                                if lb > la {
                                    continue;
                                }
                                let db = jb.derivatives[t];
                                let h = da[0]
                                    * (hc[2 * ca][2 * cb] * db[0] + hc[2 * ca][2 * cb + 1] * db[1])
                                    + da[1]
                                        * (hc[2 * ca + 1][2 * cb] * db[0]
                                            + hc[2 * ca + 1][2 * cb + 1] * db[1]);
                                slot[packed_index(la, lb)] += h / m;
                            }
                        }
                    }
                }
            });
    }

    /// The Newton step at `map`, its slope along the gradient, and whether the Hessian was
    /// factored afresh for it (damped, when the last factorization is stale; a chord step
    /// otherwise); `None` when the Hessian cannot be factored or solved with.
    fn newton_step(&mut self, map: &CircleMap, target: &[f64]) -> Option<(Vec<f64>, f64, bool)> {
        let p = self.p;
        let (x, u) = (&map.x, &map.u);
        let m = p.faces.len() as f64;
        let refactor = self.stale >= REUSE;
        let image = |f: &[u32; 3]| f.map(|v| [x[v as usize][0], x[v as usize][1]]);
        let corner: Vec<Option<CornerDerivatives>> = p
            .faces
            .par_iter()
            .zip(self.faces.par_iter().zip(target.par_iter()))
            .map(|(f, (face, &k))| {
                energy::derivatives(face, image(f), k, p.alpha, p.misfit).map(|(_, g, h)| (g, h))
            })
            .collect();
        // The chain rule to the unknowns: element matrices in parallel, the gradient after.
        if refactor {
            self.assemble_elements(u, &corner);
        }
        let grad = &mut self.grad;
        grad.iter_mut().for_each(|g| *g = 0.0);
        for (f, cd) in p.faces.iter().zip(&corner) {
            let Some((gc, _)) = cd else { continue };
            for (c, &v) in f.iter().enumerate() {
                let j = self.params.jacobian(v as usize, u);
                for s in 0..j.count {
                    let d = j.derivatives[s];
                    grad[j.unknowns[s]] += (d[0] * gc[2 * c] + d[1] * gc[2 * c + 1]) / m;
                }
            }
        }
        if refactor {
            let (pattern, values, n) = (&self.pattern, &mut self.values, self.params.n);
            pattern.assemble(&self.element_values, values);
            // Levenberg–Marquardt damping, a multiple of the mean diagonal; it also keeps the
            // matrix definite (the energy does not change when the whole map turns).
            let diag_mean =
                (0..n).map(|c| values[pattern.col_ptr()[c]]).sum::<f64>() / n.max(1) as f64;
            for c in 0..n {
                values[pattern.col_ptr()[c]] += (self.damping * diag_mean).max(f64::MIN_POSITIVE);
            }
            if self.solver.factor(&self.values).is_err() {
                return None;
            }
            self.stale = 0;
        } else {
            self.stale += 1;
        }
        let mut step: Vec<f64> = self.grad.iter().map(|g| -g).collect();
        if self.solver.solve_finite_in_place(&mut step).is_err() {
            return None;
        }
        let slope: f64 = step.iter().zip(&self.grad).map(|(s, g)| s * g).sum();
        Some((step, slope, refactor))
    }
}

impl Flow for Newton<'_, '_> {
    type Map = CircleMap;
    type Data = Energy;

    /// The energy of `map` after retargeting (the faces' area moves with the holes), its
    /// vertex density's spread, and the decrease the last advance found possible there.
    fn measure(&mut self, map: &CircleMap) -> Result<Measured<Energy>> {
        let target = face_targets(self.p, &self.faces, self.total_population, &map.x);
        let Some(energy) =
            mean_energy(self.p, &self.faces, &target, &map.x).or(self.accepted.take())
        else {
            return Err(crate::Error::Numerical(
                "the map to improve folds a triangle".into(),
            ));
        };
        self.accepted = None;
        Ok(Measured {
            error: self.decrease.take().unwrap_or(f64::INFINITY),
            merit: energy,
            data: Energy {
                target,
                spread: density_spread(self.p, &self.incidence, &map.x),
            },
        })
    }

    fn shown(&self, m: &Measured<Energy>) -> f64 {
        m.data.spread
    }

    /// One Newton step from `map` with its line search (the asked length is always 1). A
    /// decrement below the tolerance on a fresh, undamped Hessian, or no step that lowers the
    /// energy, leaves the map as it is with the decrease found; a decrement below it on a
    /// chord step or a damped Hessian (only an estimate, damping shrinks it) leaves the map as
    /// it is and renews the Hessian undamped for the next step.
    fn advance(
        &mut self,
        map: &CircleMap,
        m: &Measured<Energy>,
        _h: f64,
    ) -> Result<Moved<CircleMap>> {
        let p = self.p;
        let current = m.merit;
        let unmoved = |decrease: Option<f64>, flow: &mut Self| {
            flow.decrease = decrease;
            Ok(Moved {
                map: map.clone(),
                fraction: 0.0,
            })
        };
        let Some((step, slope, refactor)) = self.newton_step(map, &m.data.target) else {
            return unmoved(Some(0.0), self);
        };
        // The Newton decrement: the decrease a full step would make on the quadratic model.
        let predicted = -0.5 * slope / current.abs().max(f64::MIN_POSITIVE);
        if !(predicted >= p.tolerance) || current <= NEGLIGIBLE_ENERGY {
            if current <= NEGLIGIBLE_ENERGY {
                return unmoved(Some(0.0), self);
            }
            if refactor && self.damping <= MIN_DAMPING {
                return unmoved(Some(if predicted.is_nan() { 0.0 } else { predicted }), self);
            }
            self.stale = usize::MAX;
            self.damping = MIN_DAMPING;
            return unmoved(None, self);
        }
        let (x, u) = (&map.x, &map.u);
        let params = &self.params;
        // Start the line search short of the first collapse along the step (to first order).
        let collapse = collapse_times(p, params, u, x, &step);
        let t_collapse = collapse.iter().copied().fold(f64::INFINITY, f64::min);
        let mut trial = x.clone();
        let (faces, target) = (&self.faces, &m.data.target);
        let mut evaluate = |un: &[f64]| {
            params.write(un, &mut trial);
            mean_energy(p, faces, target, &trial)
        };
        let mut accepted = line_search(params, u, &step, slope, t_collapse, current, &mut evaluate);
        // A step cut short by a few faces about to collapse: the step with the vertices
        // around them held ([`HELD_RINGS`]) goes further everywhere else. It is taken when it
        // lowers the energy more, and counts as a full step (the quadratic model held where
        // it was followed).
        if accepted.as_ref().is_none_or(|a| a.length < 1.0) {
            let blocking = p
                .faces
                .iter()
                .zip(&collapse)
                .filter(|(_, t)| **t < 1.0 / COLLAPSE_MARGIN)
                .flat_map(|(f, _)| *f);
            let neighbours = self
                .neighbours
                .get_or_init(|| vertex_neighbours(x.len(), p.faces));
            let held = ring_distances(neighbours, blocking, HELD_RINGS);
            let mut partial = step.clone();
            for v in (0..held.len()).filter(|&v| held[v] != usize::MAX) {
                let j = params.jacobian(v, u);
                for &k in &j.unknowns[..j.count] {
                    partial[k] = 0.0;
                }
            }
            let partial_slope: f64 = partial.iter().zip(&self.grad).map(|(s, g)| s * g).sum();
            if partial_slope < 0.0 {
                let t_partial = collapse_times(p, params, u, x, &partial)
                    .into_iter()
                    .fold(f64::INFINITY, f64::min);
                let other = line_search(
                    params,
                    u,
                    &partial,
                    partial_slope,
                    t_partial,
                    current,
                    &mut evaluate,
                );
                if let Some(o) = other
                    && accepted.as_ref().is_none_or(|a| o.energy < a.energy)
                {
                    accepted = Some(Accepted { length: 1.0, ..o });
                }
            }
        }
        let Some(Accepted {
            unknowns: un,
            energy: e,
            length: t,
        }) = accepted
        else {
            // No step lowers the energy: a minimum (to rounding).
            return unmoved(Some(0.0), self);
        };
        params.write(&un, &mut trial);
        // A shortened step means the quadratic model was too optimistic: damp more, and
        // factorize again.
        self.damping = if t == 1.0 {
            (self.damping * 0.25).max(MIN_DAMPING)
        } else {
            self.stale = usize::MAX;
            (self.damping * 4.0).min(MAX_DAMPING)
        };
        self.accepted = Some(e);
        Ok(Moved {
            map: CircleMap { x: trial, u: un },
            fraction: 1.0,
        })
    }
}

/// Minimises the energy over the circle domain maps starting from the bijective map `x`
/// (vertices outside the problem's faces are left alone) on the density-equalizing iteration
/// ([`iterate`]) with the rules of [`rules`], reporting sd/mean of the vertex density after
/// every Newton step to `progress`.
pub(crate) fn minimize(p: &Problem, x: &mut [[f64; 3]], progress: ProgressFn) -> Result<Outcome> {
    let (mut flow, map) = Newton::new(p, x)?;
    let out = iterate(&mut flow, map, &rules(p), progress)?;
    x.copy_from_slice(&out.map.x);
    Ok(Outcome {
        iterations: out.iterations,
        history: out.history,
        converged: out.stop_reason != StopReason::MaxIter,
    })
}

/// The iteration's rules for Newton's method on `p`: the flow's own step (Newton's, with its
/// line search), stop when the decrease still possible (the Newton decrement) or the decrease
/// made over the last [`STALL_ITERATIONS`] steps falls below the tolerance, return the last
/// map (every step lowered the energy).
fn rules(p: &Problem) -> Rules {
    Rules {
        epsilon: p.tolerance,
        max_iter: p.max_iterations,
        step: Step::Own,
        stationary: Some(Stationary::Decrease {
            window: STALL_ITERATIONS,
            min_gain: p.tolerance,
        }),
        keep: Keep::Last,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One triangle with every corner free: the unknowns are its corners' coordinates.
    fn triangle() -> (Vec<[f64; 3]>, Vec<[u32; 3]>, Parameters) {
        let x = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let faces = vec![[0, 1, 2]];
        let params = Parameters::new(3, &faces, &[], &[], &[], false);
        (x, faces, params)
    }

    #[test]
    fn collapse_times_follow_a_corner_through_the_opposite_edge() {
        let (x, faces, params) = triangle();
        let u = params.read(&x, &[]);
        // Corner 2 moves down by 2 per unit step: it reaches the edge (y = 0) at t = 1/2.
        let mut step = vec![0.0; params.n];
        let k = params.jacobian(2, &u).unknowns[1];
        step[k] = -2.0;
        let p = Problem {
            surface: &x,
            faces: &faces,
            population: &[1.0],
            outer: &[],
            holes: &[],
            pinned: &[],
            fixed_holes: false,
            alpha: 0.0,
            misfit: Misfit::Square,
            max_iterations: 1,
            tolerance: 1e-6,
        };
        let t = collapse_times(&p, &params, &u, &x, &step);
        assert!((t[0] - 0.5).abs() < 1e-12, "{t:?}");
        // Moving away from the edge never collapses it.
        step[k] = 2.0;
        assert!(collapse_times(&p, &params, &u, &x, &step)[0].is_infinite());
    }

    #[test]
    fn the_line_search_starts_short_of_collapse_and_backtracks_until_armijo_holds() {
        let (x, _, params) = triangle();
        let u = params.read(&x, &[]);
        let step = vec![1.0; params.n];
        // A quadratic along the step with its minimum at t = 0.3: from t = 0.9 · 0.5 = 0.45
        // the energy 1 − t(0.6 − t) meets Armijo's condition at once.
        let at = |un: &[f64]| un[0] - u[0];
        let mut quadratic = |un: &[f64]| Some(1.0 - at(un) * (0.6 - at(un)));
        let a = line_search(&params, &u, &step, -0.6, 0.5, 1.0, &mut quadratic).unwrap();
        assert!((a.length - 0.45).abs() < 1e-12);
        assert!((a.unknowns[0] - (u[0] + 0.45)).abs() < 1e-12);
        // A map that folds beyond t = 0.1 (no energy) is backtracked below it.
        let mut folding = |un: &[f64]| (at(un) <= 0.1).then(|| 1.0 - at(un));
        let a = line_search(&params, &u, &step, -1.0, f64::INFINITY, 1.0, &mut folding).unwrap();
        assert_eq!(a.length, 0.0625);
        // No length lowers the energy: none is accepted.
        let mut rising = |un: &[f64]| Some(1.0 + at(un));
        assert!(line_search(&params, &u, &step, -1.0, 1.0, 1.0, &mut rising).is_none());
    }
}
