//! `demkit register`: one genus-0 surface carried onto another through landmark-matched
//! spherical density-equalizing maps.

use crate::Failure;
use crate::args::RegisterArgs;

/// Runs the register command; returns the exit code.
pub fn run(_a: &RegisterArgs) -> Result<u8, Failure> {
    Err(Failure::not_implemented("demkit register"))
}
