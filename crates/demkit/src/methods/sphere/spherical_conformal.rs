//! The spherical conformal parameterization on its own (`--method spherical-conformal`): the
//! initial map of SDEM (§3.1.1), with the Möbius correction towards the population.

use super::input::{check_sphere_input, initial_sphere_map};
use crate::linalg::VertexOrder;
use crate::methods::{MapResult, StopReason};
use crate::{Result, TriMesh};
use std::time::Instant;

/// Computes the spherical conformal map of `mesh` (a genus-0 closed surface), composed with the
/// Möbius transformation that best matches its face areas to `population` (`area`: the Möbius
/// area correction).
pub fn run(mesh: &TriMesh, population: &[f64]) -> Result<MapResult> {
    check_sphere_input(mesh, population, "spherical-conformal")?;
    let t0 = Instant::now();
    let mut notes = Vec::new();
    let order = VertexOrder::of_mesh(mesh.n_vertices(), &mesh.faces)?;
    let map = initial_sphere_map(mesh, population, &order, &mut notes)?;
    let mut result = MapResult::new(
        "spherical-conformal",
        map.clone(),
        map,
        StopReason::Tolerance,
        0,
        Vec::new(),
    );
    result.time_init = t0.elapsed().as_secs_f64();
    result.notes = notes;
    Ok(result)
}
