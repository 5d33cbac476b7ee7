//! The Gauss–Newton iteration on the circle constraints: step control, the penalty phase that
//! pulls the holes onto their circles, the stiffening of folding faces, and validity checks.

use super::*;

pub(super) struct Outcome {
    pub(super) iterations: usize,
    pub(super) converged: bool,
    pub(super) initial_energy: f64,
}

/// Where the iteration is: pulling the holes onto circles by the penalty (C5) with weight `λ`,
/// or with the boundary on the circles (C3) — `feasible` once it is exactly on them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Phase {
    Penalty(f64),
    Circles { feasible: bool },
}

/// The Gauss–Newton iteration, with the interior correction and the face weights of the
/// module documentation.
pub(super) struct GaussNewton<'a> {
    pub(super) geo: &'a Geometry,
    pub(super) loops: &'a [Vec<u32>],
    pub(super) penalty: Option<NormalSystem>,
    pub(super) circles: NormalSystem,
    pub(super) interior: NormalSystem,
    pub(super) interior_factored: bool,
    pub(super) weights: Vec<f64>,
}

/// A tried step: the state it gives, the faces it flips.
pub(super) struct Trial {
    pub(super) state: State,
    pub(super) flipped: Vec<u32>,
}

impl<'a> GaussNewton<'a> {
    pub(super) fn new(
        geo: &'a Geometry,
        loops: &'a [Vec<u32>],
        pin: Option<u32>,
        outer_pins: &[u32],
    ) -> Result<Self> {
        let layout = |holes| Layout::new(geo.n, loops, pin, outer_pins, holes);
        let order = geo.vertex_order()?;
        let penalty = if loops.len() > 1 {
            Some(NormalSystem::new(geo, layout(Holes::Penalized), &order)?)
        } else {
            None
        };
        Ok(Self {
            geo,
            loops,
            penalty,
            circles: NormalSystem::new(geo, layout(Holes::OnCircles), &order)?,
            interior: NormalSystem::new(geo, Layout::interior(geo.n, loops, pin), &order)?,
            interior_factored: false,
            weights: vec![1.0; geo.faces.len()],
        })
    }

    /// The unknowns of the phase.
    pub(super) fn layout(&self, phase: Phase) -> &Layout {
        match (phase, self.penalty.as_ref()) {
            (Phase::Penalty(_), Some(p)) => &p.layout,
            _ => &self.circles.layout,
        }
    }

    /// The objective of the phase: (C2) with the current weights, plus (C5).
    pub(super) fn merit(&self, state: &State, phase: Phase) -> f64 {
        let e = self.geo.conformal_energy(&state.z, Some(&self.weights));
        match (phase, &self.penalty) {
            (Phase::Penalty(lambda), Some(p)) => {
                e + lambda
                    * p.layout
                        .penalized
                        .iter()
                        .map(|p| state.off_circle(p.vertex, p.hole).powi(2))
                        .sum::<f64>()
            }
            _ => e,
        }
    }

    /// Largest distance of a hole vertex from its circle, relative to the radius.
    pub(super) fn largest_off_circle(&self, state: &State) -> f64 {
        self.loops
            .iter()
            .enumerate()
            .skip(1)
            .flat_map(|(h, lp)| lp.iter().map(move |&v| (v, h as u32)))
            .map(|(v, h)| state.off_circle(v, h).abs() / state.radii[h as usize])
            .fold(0.0, f64::max)
    }

    /// Iterates from `state` until convergence, the iteration cap, or a step that cannot be
    /// taken without folding the map.
    pub(super) fn run(&mut self, state: &mut State) -> Result<Outcome> {
        let mut phase = if self.penalty.is_some() {
            Phase::Penalty(LAMBDA_START)
        } else {
            Phase::Circles { feasible: true }
        };
        let mut outcome = Outcome {
            iterations: 0,
            converged: self.circles.layout.n_unknowns == 0,
            initial_energy: self.geo.conformal_energy(&state.z, None),
        };
        if self.circles.layout.n_unknowns == 0 {
            return Ok(outcome);
        }
        while outcome.iterations < MAX_ITERATIONS {
            let lin = circle_constraints(state, self.loops);
            let (delta, full, stiffened) =
                self.stiffened_step(state, &lin, phase, &mut outcome.iterations)?;
            let merit = self.merit(state, phase);
            let largest = delta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let Some((next, alpha)) = self.line_search(state, &lin, &delta, merit, phase, full)?
            else {
                break;
            };
            *state = next;
            phase = match phase {
                Phase::Penalty(_) if self.largest_off_circle(state) <= PENALTY_TOLERANCE => {
                    Phase::Circles { feasible: false }
                }
                Phase::Penalty(lambda) if alpha == 1.0 => Phase::Penalty(lambda * LAMBDA_GROWTH),
                Phase::Circles { feasible: false } if alpha == 1.0 => {
                    outcome.initial_energy = self.geo.conformal_energy(&state.z, None);
                    Phase::Circles { feasible: true }
                }
                Phase::Circles { feasible: true } if !stiffened => {
                    let decrease = merit - self.merit(state, phase);
                    let small = largest < STEP_TOLERANCE
                        || (alpha == 1.0 && decrease <= ENERGY_TOLERANCE * (merit - decrease));
                    if small {
                        outcome.converged = true;
                        break;
                    }
                    phase
                }
                _ => phase,
            };
        }
        if phase != (Phase::Circles { feasible: true }) {
            outcome.converged = false;
        }
        Ok(outcome)
    }

    /// The step of the phase and the state after it in full; while the full step folds
    /// triangles, they are stiffened and the step recomputed (at most [`MAX_STIFFEN_ROUNDS`]
    /// times). Every step counts as an iteration. Also returns whether weights changed.
    pub(super) fn stiffened_step(
        &mut self,
        state: &State,
        lin: &Linearization,
        phase: Phase,
        iterations: &mut usize,
    ) -> Result<(Vec<f64>, Trial, bool)> {
        *iterations += 1;
        let mut delta = self.step(state, lin, phase)?;
        let mut full = self.moved(state, lin, &delta, 1.0, phase)?;
        let mut rounds = 0;
        while !full.flipped.is_empty()
            && rounds < MAX_STIFFEN_ROUNDS
            && *iterations < MAX_ITERATIONS
            && self.stiffen(&full.flipped)
        {
            rounds += 1;
            *iterations += 1;
            delta = self.step(state, lin, phase)?;
            full = self.moved(state, lin, &delta, 1.0, phase)?;
        }
        Ok((delta, full, rounds > 0))
    }

    /// The Gauss–Newton step of the phase: the minimiser of the quadratic model of (C2) (plus
    /// the linearised (C5)) over the phase's unknowns.
    pub(super) fn step(
        &mut self,
        state: &State,
        lin: &Linearization,
        phase: Phase,
    ) -> Result<Vec<f64>> {
        let lambda = match phase {
            Phase::Penalty(l) => l,
            Phase::Circles { .. } => 0.0,
        };
        // On the circles, the model is taken at the boundary moved onto them.
        let target: Vec<C64> = match phase {
            Phase::Penalty(_) => state.z.clone(),
            Phase::Circles { .. } => state
                .z
                .iter()
                .zip(&lin.offset)
                .map(|(&z, &o)| z + o)
                .collect(),
        };
        let y = self.geo.gradient(&target, &self.weights);
        let curvature = match phase {
            Phase::Circles { .. } => Some((&y[..], &state.radii[..])),
            Phase::Penalty(_) => None,
        };
        let sys = match (phase, self.penalty.as_mut()) {
            (Phase::Penalty(_), Some(p)) => p,
            _ => &mut self.circles,
        };
        sys.factor(self.geo, &self.weights, &lin.u, lambda, curvature)?;
        let g = sys.gradient(&y, &lin.u, state, lambda);
        sys.solve(g)
    }

    /// Multiplies the weights of the `flipped` faces and of the faces sharing a vertex with
    /// them by [`STIFFEN`] (up to [`MAX_WEIGHT`]). True if a weight changed.
    pub(super) fn stiffen(&mut self, flipped: &[u32]) -> bool {
        let mut changed = false;
        let mut mark = vec![false; self.weights.len()];
        for &t in flipped {
            for &v in &self.geo.faces[t as usize] {
                for &s in self.geo.faces_around(v as usize) {
                    mark[s as usize] = true;
                }
            }
        }
        for (w, m) in self.weights.iter_mut().zip(mark) {
            if m && *w < MAX_WEIGHT {
                *w = (*w * STIFFEN).min(MAX_WEIGHT);
                changed = true;
            }
        }
        if changed {
            self.interior_factored = false;
        }
        changed
    }

    /// The largest step `α δ`, α = 1, ½, ¼, …, whose image is valid and does not increase the
    /// phase's objective (not checked before the boundary first reaches its circles); `full`
    /// is the step with α = 1.
    pub(super) fn line_search(
        &mut self,
        state: &State,
        lin: &Linearization,
        delta: &[f64],
        merit: f64,
        phase: Phase,
        full: Trial,
    ) -> Result<Option<(State, f64)>> {
        let mut alpha = 1.0;
        let mut trial = full;
        for _ in 0..MAX_HALVINGS {
            let check = match phase {
                Phase::Penalty(_) => Check::Outer,
                Phase::Circles { feasible: false } if alpha < 1.0 => Check::Loops,
                Phase::Circles { .. } => Check::Circles,
            };
            let ok = trial.flipped.is_empty()
                && invalidity(&trial.state, self.loops, check).is_none()
                && (phase == Phase::Circles { feasible: false }
                    || self.merit(&trial.state, phase) <= merit * (1.0 + 1e-12) + 1e-300);
            if ok {
                return Ok(Some((trial.state, alpha)));
            }
            alpha *= 0.5;
            trial = self.moved(state, lin, delta, alpha, phase)?;
        }
        Ok(None)
    }

    /// The state after the step `α δ`: circles change by `α (δc, δρ)`, vertices on circles
    /// slide along them (C4) — off-circle ones (before the first full step) keep the fraction
    /// `1 − α` of their offset — free boundary vertices move by `α δ`, and the interior moves
    /// by `α` times its correction to the minimiser of (C2) for the new boundary.
    pub(super) fn moved(
        &mut self,
        state: &State,
        lin: &Linearization,
        delta: &[f64],
        alpha: f64,
        phase: Phase,
    ) -> Result<Trial> {
        let mut centers = state.centers.clone();
        let mut radii = state.radii.clone();
        let mut z = state.z.clone();
        {
            let layout = self.layout(phase);
            for l in 1..self.loops.len() {
                let h = layout.hole_base[l] as usize;
                centers[l] += alpha * C64::new(delta[h], delta[h + 1]);
                radii[l] += alpha * delta[h + 2];
            }
            for &v in self.loops.iter().flatten() {
                let v = v as usize;
                z[v] = match layout.role[v] {
                    Role::Free(x) => {
                        let x = x as usize;
                        z[v] + alpha * C64::new(delta[x], delta[x + 1])
                    }
                    Role::Pinned => z[v],
                    Role::Boundary { lp, s } => {
                        let (c, r) = (centers[lp as usize], radii[lp as usize]);
                        let s = s.map_or(0.0, |s| delta[s as usize]);
                        let turn = C64::from_polar(1.0, alpha * s / r);
                        c + r * lin.u[v] * turn - (1.0 - alpha) * lin.offset[v]
                    }
                };
            }
        }
        if !self.interior_factored {
            self.interior
                .factor(self.geo, &self.weights, &[], 0.0, None)?;
            self.interior_factored = true;
        }
        let y = self.geo.gradient(&z, &self.weights);
        let g = self.interior.layout.pull_back(&y, &[]);
        let correction = self.interior.solve(g)?;
        for (v, w) in z.iter_mut().enumerate() {
            if let Role::Free(x) = self.interior.layout.role[v] {
                let x = x as usize;
                *w += alpha * C64::new(correction[x], correction[x + 1]);
            }
        }
        let flipped = flipped_faces(&z, &self.geo.faces);
        Ok(Trial {
            state: State { z, centers, radii },
            flipped,
        })
    }
}

/// What [`invalidity`] checks beyond positive radii.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Check {
    /// The outer loop winds once, counter-clockwise, step by step.
    Outer,
    /// Every loop winds once around its circle's centre in its direction.
    Loops,
    /// The loops, and the holes inside the unit circle and apart.
    Circles,
}

/// The first reason the circles and loops of `state` do not form a circle domain, if any: a
/// radius that is not positive, a loop that does not wind once around its circle's centre in
/// its direction step by step (counter-clockwise for the outer loop, clockwise for the holes),
/// a hole reaching the unit circle or another hole — as far as `check` asks.
pub(super) fn invalidity(state: &State, loops: &[Vec<u32>], check: Check) -> Option<String> {
    let finite = |c: C64| c.re.is_finite() && c.im.is_finite();
    if !state.radii.iter().all(|&r| r > 0.0 && r.is_finite())
        || !state.centers.iter().all(|&c| finite(c))
    {
        return Some("a circle has a non-positive or non-finite radius".into());
    }
    if check == Check::Circles {
        for i in 1..loops.len() {
            if state.centers[i].norm() + state.radii[i] >= 1.0 {
                return Some(format!("hole {i} reaches the unit circle"));
            }
            for j in 1..i {
                if (state.centers[i] - state.centers[j]).norm() <= state.radii[i] + state.radii[j] {
                    return Some(format!("holes {j} and {i} overlap"));
                }
            }
        }
    }
    let n_checked = if check == Check::Outer {
        1
    } else {
        loops.len()
    };
    for (l, lp) in loops.iter().enumerate().take(n_checked) {
        let c = state.centers[l];
        let sign = if l == 0 { 1.0 } else { -1.0 };
        let mut turn = 0.0;
        for k in 0..lp.len() {
            let a = state.z[lp[k] as usize] - c;
            let b = state.z[lp[(k + 1) % lp.len()] as usize] - c;
            let step = (a.conj() * b).arg() * sign;
            if !(step > 0.0) {
                return Some(format!(
                    "boundary loop {l} turns back at its vertex {}",
                    lp[k]
                ));
            }
            turn += step;
        }
        if (turn - TAU).abs() > 1e-6 {
            return Some(format!(
                "boundary loop {l} does not wind once around its circle"
            ));
        }
    }
    None
}

/// Faces whose planar image has a signed area ≤ 0 (or is not finite).
pub(super) fn flipped_faces(z: &[C64], faces: &[[u32; 3]]) -> Vec<u32> {
    let p = |v: u32| {
        let w = z[v as usize];
        [w.re, w.im, 0.0]
    };
    (0..faces.len() as u32)
        .into_par_iter()
        .filter(|&t| {
            let f = faces[t as usize];
            !(signed_area_2d(p(f[0]), p(f[1]), p(f[2])) > 0.0)
        })
        .collect()
}

pub(super) fn count_flips(z: &[C64], faces: &[[u32; 3]]) -> usize {
    flipped_faces(z, faces).len()
}
