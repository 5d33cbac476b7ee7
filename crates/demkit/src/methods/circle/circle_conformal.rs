//! The conformal map onto a circle domain on its own (`--method circle-conformal`): the
//! initial map of DEQ (§5.1.1).

use super::deq::{circle_input, initial_circle_domain, with_chords_split};
use super::refusal::{PLANAR_STAND_IN, numerical, planar_stand_in, refused};
use crate::methods::{MapResult, StopReason};
use crate::{Result, TriMesh};
use std::time::Instant;

/// The largest mean |μ| (from the surface to the map) of a map reported as conformal: a
/// discrete conformal map of a surface it can represent stays far below (0.03–0.08 on the
/// papers' surfaces and on holes cut into scans); one that had to stiffen a corridor crushed
/// towards the limits of double precision to stay bijective is far above (0.8–0.9).
const MAX_MEAN_MU: f64 = 0.25;

/// What the stand-in of a refused run is when DEQ's initial map could be computed.
const DEQ_STAND_IN: &str =
    "DEQ's initial map instead (a bijective map onto a circle domain, not conformal)";

/// Computes the conformal map of `mesh` (a connected open genus-0 surface) onto the unit disk
/// minus one round hole per inner boundary loop, among the equivalent ones (up to disk
/// automorphisms) the one whose areas best match `population`. When that map cannot be
/// computed (it would shrink a region below double precision, or its iteration breaks down or
/// ends folded), the run is refused ([`super::refusal`]) with DEQ's initial map as the
/// stand-in, or the surface laid flat when that fails too. A bijective map far from conformal
/// (mean |μ| above 0.25: the iteration had to stiffen a crushed corridor to keep it
/// bijective) is returned not converged, the reason in its notes.
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
    let computed = crate::init::circle_domain::circle_domain_map_with_report(mesh, loops);
    let (domain, report) = match numerical(computed)? {
        Ok(found) => found,
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
    let positions = domain.positions;
    let mu = crate::metrics::compute(
        mesh,
        population,
        &positions,
        &positions,
        crate::metrics::Domain::Plane,
        None,
    )
    .mean_abs_mu;
    let conformal = mu <= MAX_MEAN_MU;
    let stop_reason = if conformal {
        StopReason::Tolerance
    } else {
        StopReason::MaxIter
    };
    let mut result = MapResult::new(
        "circle-conformal",
        positions.clone(),
        positions,
        stop_reason,
        0,
        Vec::new(),
    );
    if !conformal {
        result.notes.push(format!(
            "the conformal map could not be computed accurately: its mean |mu| is {mu:.3} \
             (above {MAX_MEAN_MU}), {} faces were stiffened to keep it bijective; part of the \
             surface is shrunk towards the limits of double precision (a long corridor, such \
             as a spiral); the result is that bijective circle domain map",
            report.stiffened_faces
        ));
    }
    result.time_init = t0.elapsed().as_secs_f64();
    Ok(result)
}
