//! What a method returns: the map, how its iteration ended, and what it reports on the way.

/// Why an iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The method's stopping quantity fell below ε.
    Tolerance,
    /// The map stopped improving before reaching ε (still converged).
    Stationary,
    /// The iteration limit ran out (not converged).
    MaxIter,
}

impl StopReason {
    /// The report's name for the reason.
    pub fn as_str(&self) -> &'static str {
        match self {
            StopReason::Tolerance => "tolerance",
            StopReason::Stationary => "stationary",
            StopReason::MaxIter => "max_iter",
        }
    }
}

/// What a long run reports after each iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// 1-based iteration number.
    pub iteration: usize,
    /// The iteration limit.
    pub max_iter: usize,
    /// The method's own stopping quantity (e.g. sd/mean of the density).
    pub error: f64,
}

/// The outcome of a method.
#[derive(Debug, Clone)]
pub struct MapResult {
    /// The method's report name (`"dem"`, ...).
    pub method: &'static str,
    /// The mapped position of every input vertex, in input order (z = 0 for planar maps).
    pub positions: Vec<[f64; 3]>,
    /// The initial map (after initialization, before density equalization), same scale as
    /// `positions`; metrics compare the two.
    pub initial: Vec<[f64; 3]>,
    /// True unless the iteration limit ran out.
    pub converged: bool,
    /// Why the iteration stopped.
    pub stop_reason: StopReason,
    /// Number of iterations done.
    pub iterations: usize,
    /// The stopping quantity after each iteration.
    pub history: Vec<f64>,
    /// Seconds spent in the initialization.
    pub time_init: f64,
    /// Seconds spent in the density-equalizing iteration.
    pub time_map: f64,
    /// Remarks worth telling the user (e.g. an initial map fell back to Tutte).
    pub notes: Vec<String>,
    /// For maps onto a torus: the final map on the flat torus (points and lattice
    /// translations), from which `positions` is projected; flips are counted on it.
    pub flat_torus: Option<crate::geometry::torus::FlatTorusMap>,
    /// For maps onto an ellipsoid (EDEM, EDEQ): the ellipsoid, in the radii asked for (EDEQ's
    /// are the ones it chose); `positions` lie on it.
    pub ellipsoid: Option<crate::geometry::ellipsoid::Ellipsoid>,
    /// The surface the map is of, when the method had to refine its input (DEQ: the chords of
    /// holes split, [`deq`]); `positions` and `initial` then follow its vertices, the input's
    /// first in their order.
    pub refined: Option<RefinedSurface>,
    /// `[initial, final]` values of the method's own objective, when it minimises one that
    /// weighs the density against something else (DEQ: density misfit and distortion, (4.2));
    /// [`judge`](Self::judge) measures the run's progress on it instead of on the density.
    pub objective: Option<[f64; 2]>,
    /// True when the method could not compute its map at all (a circle domain map that would
    /// shrink part of the surface below double precision, a factorization that broke down):
    /// `positions` is then the best stand-in it had, possibly not bijective, the run is not
    /// converged (stop reason `max_iter`) and the first note says why.
    pub refused: bool,
}

/// A refinement of the input a method mapped instead of the input itself.
#[derive(Debug, Clone, PartialEq)]
pub struct RefinedSurface {
    /// The refined mesh: the input vertices first, in input order, then the added ones.
    pub mesh: crate::TriMesh,
    /// The population of each of its faces (each input face's shared among its parts by area).
    pub population: Vec<f64>,
    /// The input face each of its faces is part of.
    pub parent_face: Vec<usize>,
}

impl MapResult {
    /// The map of `method` from `initial` to `positions`, stopped for `stop_reason` after
    /// `iterations` with the stopping quantity's `history`: converged unless the limit ran out;
    /// no times, notes or extras yet (the method fills in what it has).
    pub(crate) fn new(
        method: &'static str,
        positions: Vec<[f64; 3]>,
        initial: Vec<[f64; 3]>,
        stop_reason: StopReason,
        iterations: usize,
        history: Vec<f64>,
    ) -> Self {
        Self {
            method,
            positions,
            initial,
            converged: stop_reason != StopReason::MaxIter,
            stop_reason,
            iterations,
            history,
            time_init: 0.0,
            time_map: 0.0,
            notes: Vec::new(),
            flat_torus: None,
            ellipsoid: None,
            refined: None,
            objective: None,
            refused: false,
        }
    }

    /// Makes `converged` honest: a run its method calls converged is not (stop reason
    /// `max_iter`, the reason in the notes) when it left the density as it was
    /// ([`crate::metrics::barely_moved`] of its `metrics`; for a method with its own
    /// [`objective`](Self::objective), [`crate::metrics::barely_lowered`] of that, or a density
    /// left far from equal, [`crate::metrics::not_equalized`]), or when it stopped improving
    /// under a fixed time step `fixed_dt` short of its tolerance. The conformal maps do not equalize
    /// the density and are left as they are.
    pub fn judge(&mut self, metrics: &crate::metrics::Metrics, fixed_dt: Option<f64>) {
        if !self.converged || matches!(self.method, "spherical-conformal" | "circle-conformal") {
            return;
        }
        let stationary = self.stop_reason == StopReason::Stationary;
        let barely = match self.objective {
            Some([before, after]) => crate::metrics::barely_lowered(before, after)
                .or_else(|| crate::metrics::not_equalized(metrics)),
            None => crate::metrics::barely_moved(metrics),
        };
        let why = match (barely, fixed_dt) {
            (Some(why), Some(dt)) => {
                format!("{why}; the fixed time step {dt:e} is too small to move the map")
            }
            (Some(why), None) => why,
            // With its step fixed a run that stops improving may only be too slow to go on.
            (None, Some(dt)) if stationary => format!(
                "the map stopped improving with the fixed time step {dt:e} before reaching the \
                 tolerance; the default (adaptive) step may go further"
            ),
            (None, _) => return,
        };
        self.converged = false;
        self.stop_reason = StopReason::MaxIter;
        self.notes.push(why);
    }
}

/// A progress callback; the CLI draws a bar with it, tests pass `&mut |_| {}`.
pub type ProgressFn<'a> = &'a mut dyn FnMut(Progress);
