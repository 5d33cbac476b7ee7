//! The density-equalizing iteration every method runs: one loop, with one step rule, one stop
//! rule, best-map tracking, and one quantity in its history and its progress.
//!
//! A method supplies a [`Flow`]: how to measure a map (its stopping quantity and the merit by
//! which maps are compared) and how to advance it by a step of a given length without folding
//! it. [`iterate`] does the rest, by the [`Rules`] the method asks for:
//!
//! - **step** ([`Step`]): a fixed length, every move kept (the papers' explicit iterations); or
//!   adaptive: the step starts at the flow's longest ([`Flow::step_cap`]), a move that does not
//!   lower the merit is undone and the step halved, after one that does the next may be twice
//!   as long as the move actually made (capped again by the flow); or adaptive with a search
//!   along each direction ([`Step::Search`]): the same, but an accepted move is also tried
//!   longer along the same direction, the step grows only after a move that was not a retry,
//!   and slow progress first asks the flow for a finer scale ([`Flow::refine`]); or the flow's
//!   own (a Newton step with its line search), every move kept;
//! - **stop**: the stopping quantity below ε (tolerance); slow progress by the rule
//!   [`Stationary`] asks for, or a step that could not move the map at all (stationary); the
//!   iteration limit (not converged);
//! - **result** ([`Keep`]): the best map met, or the last one; a map that met the tolerance is
//!   returned as it is.
//!
//! Which parameters differ between the methods, and why, is written down in
//! `docs/deviations.md`.

use super::{Progress, ProgressFn, StopReason};
use crate::{Error, Result};

/// What a flow measures on a map.
#[derive(Debug, Clone)]
pub(crate) struct Measured<D> {
    /// The stopping quantity (compared with ε, recorded in the history, shown in progress).
    pub error: f64,
    /// What makes one map better than another (lower is better).
    pub merit: f64,
    /// Whatever else the flow needs from the measurement to take its next step.
    pub data: D,
}

/// A move made by a flow.
#[derive(Debug, Clone)]
pub(crate) struct Moved<M> {
    /// The map after the move (never folded).
    pub map: M,
    /// The fraction of the asked step actually taken (1 when nothing had to be shortened,
    /// 0 when the map could not move).
    pub fraction: f64,
}

/// A density-equalizing flow: the part of a method that differs from the others.
pub(crate) trait Flow {
    /// A map (positions on the plane, the sphere, the flat torus).
    type Map: Clone;
    /// What [`measure`](Self::measure) hands to [`advance`](Self::advance).
    type Data;

    /// Measures `map`.
    fn measure(&mut self, map: &Self::Map) -> Result<Measured<Self::Data>>;

    /// The quantity recorded in the history and shown in progress for a map measured as `m`:
    /// the stopping quantity, unless the method reports another one (DEQ's Newton stages stop
    /// on the energy's decrease but report sd/mean of the vertex density, as its flow does).
    fn shown(&self, m: &Measured<Self::Data>) -> f64 {
        m.error
    }

    /// The longest step an adaptive iteration may take from a map measured as `m`.
    fn step_cap(&self, _m: &Measured<Self::Data>) -> f64 {
        f64::INFINITY
    }

    /// Asked by [`Step::Search`] when progress has slowed or stalled: a flow that works at a
    /// scale it can make finer (DEM's smoothing length) switches to the finer scale and returns
    /// the factor for the step length; `None` (the default) when it has none, which lets slow
    /// progress end the run as usual.
    fn refine(&mut self) -> Option<f64> {
        None
    }

    /// Advances `map`, measured as `m`, by a step of length `h` without folding it. Under
    /// [`Step::Search`] it may be called several times with the same `map` and `m` and other
    /// lengths (a retry after a rejected move, a longer move along an accepted one); a flow
    /// should then move along the direction it computed the first time, scaled.
    fn advance(
        &mut self,
        map: &Self::Map,
        m: &Measured<Self::Data>,
        h: f64,
    ) -> Result<Moved<Self::Map>>;
}

/// How long the steps are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Step {
    /// Every step this long; every move is kept.
    Fixed(f64),
    /// Steps adapted to the flow (see the module docs).
    Adaptive,
    /// Adaptive steps with a search along each direction (see the module docs and
    /// [`RAMP_GROWTH`], [`SEARCH_DOUBLINGS`], [`REFINE_GAIN`]): one expensive direction per
    /// accepted map, its length chosen by cheap trials.
    Search,
    /// The flow chooses its own step (a Newton step and its line search): the iteration asks
    /// for a step of 1 and keeps every move. A move of fraction 0 left the map as it was (the
    /// flow renewed its model instead), which is not the end of the run: such a flow reports
    /// that it cannot improve the map through its stopping quantity.
    Own,
}

/// Which map the iteration returns when it does not meet the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Keep {
    /// The map of lowest merit met.
    Best,
    /// The last map.
    Last,
}

/// The rules of one run of the iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rules {
    /// Stop when the stopping quantity falls below this.
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// The step rule.
    pub step: Step,
    /// When slow progress ends the run as stationary (`None`: only a step that cannot move).
    pub stationary: Option<Stationary>,
    /// Which map to return.
    pub keep: Keep,
}

impl Rules {
    /// The rules of an explicit iteration with the fixed time step `dt` (SDEM's Alg. 3.1 and
    /// LSDEM's Alg. 3.2): stop below `epsilon` or after `max_iter` iterations, stationary when
    /// the best merit improves by less than `min_gain` over `window` iterations, `keep` the
    /// map asked for.
    pub(crate) fn fixed(
        epsilon: f64,
        max_iter: usize,
        dt: f64,
        window: usize,
        min_gain: f64,
        keep: Keep,
    ) -> Self {
        Self {
            epsilon,
            max_iter,
            step: Step::Fixed(dt),
            stationary: Some(Stationary::Best { window, min_gain }),
            keep,
        }
    }
}

/// Runs a flow whose stopping quantity counts what is left to do (landmarks not yet at their
/// targets, faces still far off) on the positions `x`, in place: it takes its own steps, stops
/// when nothing is left (the count below 1) or after `max_iter` iterations, and keeps the last
/// map. The flow keeps whatever it reports of its work.
pub(crate) fn count_down<F: Flow<Map = Vec<[f64; 3]>>>(
    flow: &mut F,
    x: &mut [[f64; 3]],
    max_iter: usize,
) -> Result<()> {
    let rules = Rules {
        epsilon: 1.0,
        max_iter,
        step: Step::Own,
        stationary: None,
        keep: Keep::Last,
    };
    let out = iterate(flow, x.to_vec(), &rules, &mut |_| {})?;
    x.copy_from_slice(&out.map);
    Ok(())
}

/// When slow progress makes a run stationary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Stationary {
    /// The best merit improved by less than the fraction `min_gain` of the best `window`
    /// iterations earlier: `best_k > (1 − min_gain) · best_{k−window}`.
    Best {
        /// Iterations looked back over.
        window: usize,
        /// The smallest relative improvement over `window` iterations that is still progress.
        min_gain: f64,
    },
    /// The merit fell by less than the fraction `min_gain` of its current value over the last
    /// `window` moves, `merit_{j−window} − merit_j < min_gain · merit_j` (iterations that left
    /// the map as it was do not count): the stop of a minimisation on its objective's
    /// decrease, where the merit is the objective (DEQ's Newton stages, `docs/deviations.md`).
    Decrease {
        /// Moves looked back over.
        window: usize,
        /// The smallest decrease over `window` moves, relative to the merit, that is still
        /// progress.
        min_gain: f64,
    },
}

/// After a move that lowered the merit, the next step may be this many times as long as the
/// move made.
const STEP_GROWTH: f64 = 2.0;

/// After a move that did not lower the merit, the next step is this fraction of the move made.
const STEP_SHRINK: f64 = 0.5;

/// [`Step::Search`]: until the first move that did not lower the merit, the next step may be
/// this many times as long as the move made. The first step, δt of (4.39) for DEM, can be
/// orders of magnitude below the flow's scale (the hand's initial map: 1e-8 of its area);
/// growing by 2 took 17 of the hand's 104 iterations to get there, by 4 it takes 9.
pub(crate) const RAMP_GROWTH: f64 = 4.0;

/// [`Step::Search`]: an accepted move that the flow did not have to shorten is tried up to
/// this many times again, each twice as long along the same direction, while the merit keeps
/// falling; the trials cost a move and a measurement each, not a new direction.
pub(crate) const SEARCH_DOUBLINGS: usize = 3;

/// [`Step::Search`]: an accepted full move, not a retry, that lowered the merit by less than
/// this fraction asks the flow for a finer scale ([`Flow::refine`]): at its present scale the
/// flow has reached what it can do (DEM: 3–7 % per move while there is work for the scale,
/// below 1 % at its floor).
pub(crate) const REFINE_GAIN: f64 = 0.03;

/// An adaptive iteration whose step has shrunk below this fraction of its first step has
/// stopped moving: stationary.
const SMALLEST_STEP: f64 = 1e-6;

/// The outcome of an iteration.
#[derive(Debug, Clone)]
pub(crate) struct Outcome<M> {
    /// The map returned ([`Keep`]).
    pub map: M,
    /// Iterations done.
    pub iterations: usize,
    /// The stopping quantity after each iteration.
    pub history: Vec<f64>,
    /// Why the iteration stopped.
    pub stop_reason: StopReason,
}

impl<M> Outcome<M> {
    /// The method's result from this outcome: `positions` makes the returned map the method's
    /// output (normalized onto the sphere, rotated, ...); the map's time runs from `started`.
    pub(crate) fn into_result(
        self,
        method: &'static str,
        initial: Vec<[f64; 3]>,
        positions: impl FnOnce(M) -> Vec<[f64; 3]>,
        started: std::time::Instant,
        notes: Vec<String>,
    ) -> super::MapResult {
        let positions = positions(self.map);
        let mut result = super::MapResult::new(
            method,
            positions,
            initial,
            self.stop_reason,
            self.iterations,
            self.history,
        );
        result.time_map = started.elapsed().as_secs_f64();
        result.notes = notes;
        result
    }
}

/// Checks the parameters every method shares: ε positive, a fixed time step positive, at least
/// one iteration. The messages name the parameters (`epsilon`, `dt`, `max_iter`).
pub(crate) fn check_parameters(epsilon: f64, dt: Option<f64>, max_iter: usize) -> Result<()> {
    if !(epsilon > 0.0 && epsilon.is_finite()) {
        return Err(Error::Argument(format!(
            "epsilon must be positive, got {epsilon}"
        )));
    }
    if let Some(dt) = dt.filter(|dt| !(*dt > 0.0 && dt.is_finite())) {
        return Err(Error::Argument(format!("dt must be positive, got {dt}")));
    }
    if max_iter == 0 {
        return Err(Error::Argument("max_iter must be at least 1".into()));
    }
    Ok(())
}

/// (4.39) of the DEM paper: `δt = min(min ρ / mean ρ, mean ρ / max ρ) × Area`, the longest
/// time step for the vertex density `rho_v` on a domain of area `area`.
pub(crate) fn diffusion_time_step(rho_v: &[f64], area: f64) -> f64 {
    let n = rho_v.len() as f64;
    let mean = rho_v.iter().sum::<f64>() / n;
    let min = rho_v.iter().cloned().fold(f64::INFINITY, f64::min);
    let max = rho_v.iter().cloned().fold(0.0, f64::max);
    (min / mean).min(mean / max) * area
}

/// Runs the density-equalizing iteration of `flow` from the flip-free map `initial` by `rules`
/// (see the module docs), reporting the stopping quantity after every iteration to `progress`.
pub(crate) fn iterate<F: Flow>(
    flow: &mut F,
    initial: F::Map,
    rules: &Rules,
    progress: ProgressFn,
) -> Result<Outcome<F::Map>> {
    let mut map = initial;
    let mut m = flow.measure(&map)?;
    let mut history = Vec::new();
    if m.error < rules.epsilon {
        return Ok(Outcome {
            map,
            iterations: 0,
            history,
            stop_reason: StopReason::Tolerance,
        });
    }
    let mut best = (rules.keep == Keep::Best).then(|| (m.merit, map.clone()));
    let mut best_merit = m.merit;
    let mut best_history = vec![best_merit];
    // The merit after each of the last moves, and before them ([`Stationary::Decrease`]).
    let mut moves = std::collections::VecDeque::from([m.merit]);
    let first = match rules.step {
        Step::Fixed(h) => h,
        Step::Adaptive | Step::Search => flow.step_cap(&m),
        Step::Own => 1.0,
    };
    let mut h = first;
    // Step::Search: no move has been rejected yet (the ramp); the last move was rejected; the
    // last accepted move asks for a finer scale.
    let (mut ramp, mut retry, mut slow) = (true, false, false);
    let mut stop_reason = StopReason::MaxIter;
    let mut iterations = 0;
    for it in 1..=rules.max_iter {
        iterations = it;
        let asked = match rules.step {
            Step::Fixed(h) => h,
            Step::Adaptive | Step::Search => h.min(flow.step_cap(&m)),
            Step::Own => 1.0,
        };
        let moved = flow.advance(&map, &m, asked)?;
        let next = flow.measure(&moved.map)?;
        match rules.step {
            Step::Fixed(_) | Step::Own => {
                map = moved.map;
                m = next;
            }
            Step::Adaptive if next.merit < m.merit => {
                map = moved.map;
                m = next;
                h = STEP_GROWTH * moved.fraction * asked;
            }
            Step::Adaptive => h = STEP_SHRINK * moved.fraction * asked,
            Step::Search if next.merit < m.merit => {
                // Longer moves along the same direction while the merit keeps falling.
                let (mut made, mut fraction) = (moved.fraction * asked, moved.fraction);
                let (mut best_map, mut best) = (moved.map, next);
                for _ in 0..SEARCH_DOUBLINGS {
                    if fraction < 1.0 {
                        break;
                    }
                    let longer = flow.advance(&map, &m, 2.0 * made)?;
                    let measured = flow.measure(&longer.map)?;
                    if !(longer.fraction > 0.0 && measured.merit < best.merit) {
                        break;
                    }
                    (made, fraction) = (2.0 * made * longer.fraction, longer.fraction);
                    (best_map, best) = (longer.map, measured);
                }
                slow = fraction == 1.0 && !retry && m.merit - best.merit < REFINE_GAIN * m.merit;
                let growth = match (retry, ramp) {
                    (true, _) => 1.0,
                    (false, true) => RAMP_GROWTH,
                    (false, false) => STEP_GROWTH,
                };
                h = growth * made;
                retry = false;
                map = best_map;
                m = best;
            }
            Step::Search => {
                h = STEP_SHRINK * moved.fraction * asked;
                (ramp, retry) = (false, true);
            }
        }
        let shown = flow.shown(&m);
        history.push(shown);
        progress(Progress {
            iteration: it,
            max_iter: rules.max_iter,
            error: shown,
        });
        if m.error < rules.epsilon {
            stop_reason = StopReason::Tolerance;
            best = None;
            break;
        }
        if m.merit < best_merit {
            best_merit = m.merit;
            if rules.keep == Keep::Best {
                best = Some((m.merit, map.clone()));
            }
        }
        best_history.push(best_merit);
        let k = best_history.len();
        let stalled = match rules.stationary {
            None => false,
            Some(Stationary::Best { window, min_gain }) => {
                k > window && best_merit > (1.0 - min_gain) * best_history[k - 1 - window]
            }
            Some(Stationary::Decrease { window, min_gain }) if moved.fraction > 0.0 => {
                moves.push_back(m.merit);
                if moves.len() > window + 1 {
                    moves.pop_front();
                }
                moves.len() > window && moves[0] - m.merit < min_gain * m.merit
            }
            Some(Stationary::Decrease { .. }) => false,
        };
        let stuck = match rules.step {
            Step::Fixed(_) => moved.fraction == 0.0,
            Step::Adaptive | Step::Search => !(h >= SMALLEST_STEP * first),
            Step::Own => false,
        };
        // Step::Search: slow or stalled progress first asks the flow for a finer scale; the
        // window of the stationary rule then starts again.
        if rules.step == Step::Search && (slow || stalled) && !stuck {
            slow = false;
            if let Some(factor) = flow.refine() {
                h *= factor;
                best_history.clear();
                best_history.push(best_merit);
                continue;
            }
        }
        if stalled || stuck {
            stop_reason = StopReason::Stationary;
            break;
        }
    }
    // The best map, unless the last one is (or is asked for).
    if let Some((merit, best_map)) = best
        && merit < m.merit
    {
        map = best_map;
    }
    Ok(Outcome {
        map,
        iterations,
        history,
        stop_reason,
    })
}

#[cfg(test)]
mod tests;
