//! `demkit cartogram`: GeoJSON regions resized so that each region's area follows a value.

use crate::Failure;
use crate::args::CartogramArgs;

/// Runs the cartogram command; returns the exit code.
pub fn run(_a: &CartogramArgs) -> Result<u8, Failure> {
    Err(Failure::not_implemented("demkit cartogram"))
}
