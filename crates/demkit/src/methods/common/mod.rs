//! What every method shares: the density-equalizing iteration, the result and its judgement,
//! and the input checks.

mod checks;
pub(crate) mod iteration;
mod result;

pub(crate) use checks::{check_landmark_vertices, require_valid_mesh};
pub use result::{MapResult, Progress, ProgressFn, RefinedSurface, StopReason};
