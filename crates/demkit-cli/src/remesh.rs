//! `demkit remesh`: a new triangulation of the input surface laid out through its
//! density-equalizing map.

use crate::Failure;
use crate::args::RemeshArgs;

/// Runs the remesh command; returns the exit code.
pub fn run(_a: &RemeshArgs) -> Result<u8, Failure> {
    Err(Failure::not_implemented("demkit remesh"))
}
