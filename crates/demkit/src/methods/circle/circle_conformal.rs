//! The conformal map onto a circle domain on its own (`--method circle-conformal`): the
//! initial map of DEQ (§5.1.1).

use super::deq::{circle_input, initial_circle_domain, with_chords_split};
use super::refusal::{PLANAR_STAND_IN, numerical, planar_stand_in, refused};
use crate::methods::{MapResult, StopReason};
use crate::{Result, TriMesh};
use std::time::Instant;

/// What the stand-in of a refused run is when DEQ's initial map could be computed.
const DEQ_STAND_IN: &str =
    "DEQ's initial map instead (a bijective map onto a circle domain, not conformal)";

/// Computes the conformal map of `mesh` (a connected open genus-0 surface) onto the unit disk
/// minus one round hole per inner boundary loop, among the equivalent ones (up to disk
/// automorphisms) the one whose areas best match `population`. When that map cannot be
/// computed (it would shrink a region below double precision, or its iteration breaks down or
/// ends folded), the run is refused ([`super::refusal`]) with DEQ's initial map as the
/// stand-in, or the surface laid flat when that fails too.
///
/// A mesh whose holes have chords (edges joining two vertices of the same hole, which no
/// circle domain holds outside the hole's circle) is mapped with them split, as DEQ maps it;
/// the result then carries the refined surface.
pub fn run(mesh: &TriMesh, population: &[f64]) -> Result<MapResult> {
    let loops = circle_input(mesh, population, "circle-conformal")?;
    with_chords_split(mesh, population, &loops, |mesh, population| {
        chordless(mesh, population, &loops)
    })
}

/// [`run`] on a mesh whose holes have no chords, its boundary loops `loops`.
fn chordless(mesh: &TriMesh, population: &[f64], loops: &[Vec<u32>]) -> Result<MapResult> {
    let t0 = Instant::now();
    let domain = match numerical(crate::init::circle_domain::circle_domain_map(mesh, loops))? {
        Ok(domain) => domain,
        Err(why) => {
            let mut result = match numerical(initial_circle_domain(mesh, population, loops))? {
                Ok(x) => refused("circle-conformal", x, &why, DEQ_STAND_IN),
                Err(_) => refused(
                    "circle-conformal",
                    planar_stand_in(mesh, &loops[0]),
                    &why,
                    PLANAR_STAND_IN,
                ),
            };
            result.time_init = t0.elapsed().as_secs_f64();
            return Ok(result);
        }
    };
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
