//! The conformal map onto a circle domain on its own (`--method circle-conformal`): the
//! initial map of DEQ (§5.1.1).

use super::deq::circle_input;
use crate::methods::{MapResult, StopReason};
use crate::{Result, TriMesh};
use std::time::Instant;

/// Computes the conformal map of `mesh` (a connected open genus-0 surface) onto the unit disk
/// minus one round hole per inner boundary loop, among the equivalent ones (up to disk
/// automorphisms) the one whose areas best match `population`.
pub fn run(mesh: &TriMesh, population: &[f64]) -> Result<MapResult> {
    let loops = circle_input(mesh, population, "circle-conformal")?;
    let t0 = Instant::now();
    let domain = crate::init::circle_domain::circle_domain_map(mesh, &loops)?;
    let domain = crate::init::disk_mobius::balance_areas(&domain, &mesh.faces, population);
    let mut result = MapResult::new(
        "circle-conformal",
        domain.positions.clone(),
        domain.positions,
        StopReason::Tolerance,
        0,
        Vec::new(),
    );
    result.time_init = t0.elapsed().as_secs_f64();
    Ok(result)
}
