//! The planar cartogram (DEM paper §6.1): DEM (Algorithm 5) on the regions' mesh with its sea,
//! repeated from the map reached while the regions' areas are still off their values.

use super::triangulate::RegionMesh;
use super::{Cartogram, Config, MIN_CORRECTION, Polygon, finish, unit_values};
use crate::geometry::count_nonpositive;
use crate::methods::{ProgressFn, StopReason, dem};
use crate::{Result, TriMesh};
use std::time::Instant;

/// The map's own sea (DEM's reflection sea, Algorithm 4) is truncated at this radius: the
/// mesh has its sea already, so DEM's is kept to a thin ring (measured on 2500 squares: 1.6
/// times fewer unknowns than with DEM's η = 5, the same areas, half the time).
const SEA_ETA: f64 = 1.25;

/// The mesh's farthest vertex sits at this radius of the unit disk when DEM builds its sea
/// (DEM's own default; a thinner ring, 0.95, measured worse areas on irregular cells).
const SEA_ROI_RADIUS: f64 = 0.85;

/// The rounds stop when this many in a row have not lowered the worst error, even with their
/// corrections halved: the map then only moves around the same accuracy.
const STALL_ROUNDS: usize = 3;

/// The best round so far.
struct BestRound {
    /// Its worst |area/value error|.
    worst: f64,
    /// The regions' rings.
    coordinates: Vec<Vec<Polygon>>,
    /// The mesh positions.
    positions: Vec<[f64; 3]>,
    /// The values the round was run with, and the errors it left.
    effective: Vec<f64>,
    errors: Vec<f64>,
}

/// The population of every face (DEM paper §6.1): a region's value spread over its faces in
/// proportion to their areas, and the sea at the regions' mean density (value per area), so
/// that it neither grows nor shrinks on average (GN's sea, DEM paper §3).
pub fn face_population(values: &[f64], face_region: &[Option<usize>], areas: &[f64]) -> Vec<f64> {
    let mut region_area = vec![0.0; values.len()];
    for (r, a) in face_region.iter().zip(areas) {
        if let Some(r) = r {
            region_area[*r] += a;
        }
    }
    let mean_density = values.iter().sum::<f64>() / region_area.iter().sum::<f64>();
    face_region
        .iter()
        .zip(areas)
        .map(|(r, a)| match r {
            Some(r) => values[*r] * a / region_area[*r],
            None => mean_density * a,
        })
        .collect()
}

/// Computes the planar cartogram of `set` (coordinates in the plane).
///
/// The mesh of [`RegionMesh::build`] is mapped by DEM; while the worst region's area/value is
/// more than `config.tolerance` off the mean and rounds are left, DEM runs again from the map
/// reached, with every region's value divided by 1 + its remaining error (at most by a factor
/// 2 either way per round): the discrete map is biased at the regions' borders (a vertex's
/// density averages both sides), and this fixed-point correction removes the bias. Each round
/// starts from the best one so far, with that round's correction, halved for every round
/// since that did not improve on it; the rounds stop after [`STALL_ROUNDS`] such rounds in a
/// row. The round with the smallest worst error is the result.
/// The result is scaled so that the regions' total area is the input's and moved so that their
/// area centroid is the input's. The computation runs in the set's normalised frame, on values
/// scaled to a largest value of 1, so any finite coordinates and values give the same map.
///
/// Errors: a cap outside [`super::check_max_faces`]'s range ([`crate::Error::Argument`]); a
/// mesh beyond [`super::MAX_FACES`], refused before it is built, and the mesh's own errors
/// ([`RegionMesh::build`]); DEM's.
pub fn run(
    set: &super::regions::RegionSet,
    config: &Config,
    path: &str,
    progress: ProgressFn,
) -> Result<Cartogram> {
    let t0 = Instant::now();
    super::check_max_faces(config.max_faces)?;
    let mesh = RegionMesh::build(set, &config.resolution(), path)?;
    let values = unit_values(&set.regions.iter().map(|r| r.value).collect::<Vec<_>>());
    let input: Vec<[f64; 3]> = mesh.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let areas0 = crate::geometry::face_areas(&input, &mesh.faces);
    let (c_in, a_in) = region_centroid(&input, &mesh, &areas0);

    let mut dem_config = dem::Config::default();
    if let Some(n) = config.max_iter {
        dem_config.max_iter = n;
    }
    dem_config.patience = config.patience;
    dem_config.eta = SEA_ETA;
    dem_config.roi_radius = SEA_ROI_RADIUS;
    let mut positions = input.clone();
    let mut iterations = 0;
    let mut rounds = 0;
    let mut stop_reason = StopReason::Tolerance;
    let mut notes = Vec::new();
    if let Some(n) = mesh_note(set, config, &mesh) {
        notes.push(n);
    }
    let mut best: Option<BestRound> = None;
    let mut since_best = 0;
    // The values the populations are made of: the regions' own at first, then corrected by
    // each round's remaining error (a region that came out too large gets a smaller value).
    let mut effective = values.clone();
    for round in 0..config.rounds.max(1) {
        let population = face_population(&effective, &mesh.face_region, &areas0);
        let current = TriMesh::new(positions.clone(), mesh.faces.clone());
        let r = dem::run(&current, &population, &dem_config, progress)?;
        iterations += r.iterations;
        rounds = round + 1;
        stop_reason = r.stop_reason;
        for n in r.notes {
            if !notes.contains(&n) {
                notes.push(n);
            }
        }
        // Same regions' area and centroid as the input.
        let areas = crate::geometry::face_areas(&r.positions, &mesh.faces);
        let (c, a) = region_centroid(&r.positions, &mesh, &areas);
        let k = (a_in / a).sqrt();
        positions = r
            .positions
            .iter()
            .map(|p| {
                [
                    c_in[0] + k * (p[0] - c[0]),
                    c_in[1] + k * (p[1] - c[1]),
                    0.0,
                ]
            })
            .collect();
        let coordinates = output_coordinates(set, &mesh, &positions);
        let errors = super::ratio_errors(&values, &coordinates);
        let worst = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        if best.as_ref().is_none_or(|b| worst < b.worst) {
            best = Some(BestRound {
                worst,
                coordinates,
                positions: positions.clone(),
                effective: effective.clone(),
                errors,
            });
            since_best = 0;
        } else {
            since_best += 1;
        }
        if worst <= config.tolerance
            || stop_reason == StopReason::MaxIter
            || since_best >= STALL_ROUNDS
        {
            break;
        }
        // The next round starts from the best one, with its correction, halved after every
        // round that did not improve on it (the corrections carry the map's noise too).
        let Some(b) = best.as_ref() else { break };
        let step = 0.5f64.powi(since_best as i32);
        positions.clone_from(&b.positions);
        effective = b
            .effective
            .iter()
            .zip(&b.errors)
            .map(|(v, e)| {
                v / (1.0 + e)
                    .clamp(MIN_CORRECTION, 1.0 / MIN_CORRECTION)
                    .powf(step)
            })
            .collect();
    }
    let Some(BestRound {
        coordinates,
        positions,
        ..
    }) = best
    else {
        return Err(crate::Error::Numerical("the cartogram ran no round".into()));
    };
    let flipped = count_nonpositive(&positions, &mesh.faces);
    finish(
        set,
        coordinates,
        super::Run {
            iterations,
            rounds,
            stop_reason,
            mesh_vertices: mesh.points.len(),
            mesh_faces: mesh.faces.len(),
            flipped_triangles: flipped,
            notes,
            time_s: t0.elapsed().as_secs_f64(),
        },
        path,
    )
}

/// What the mesh's size owes to the cap, when it does: fewer faces per polygon than asked, or
/// more faces than the cap because the polygons need them.
fn mesh_note(
    set: &super::regions::RegionSet,
    config: &Config,
    mesh: &RegionMesh,
) -> Option<String> {
    let polygons: usize = set.regions.iter().map(|r| r.polygons.len()).sum();
    let faces = mesh.faces.len();
    if faces as f64 > super::triangulate::CAP_SLACK * config.max_faces as f64 {
        Some(format!(
            "the mesh has {faces} faces, more than the cap of {}: {polygons} polygons need \
             about {:.0} triangles each at least",
            config.max_faces, mesh.plan.polygon_faces
        ))
    } else if mesh.plan.polygon_faces < config.polygon_faces as f64 {
        Some(format!(
            "{polygons} polygons: about {:.0} triangles each, to keep the mesh within the cap \
             of {} faces (about)",
            mesh.plan.polygon_faces, config.max_faces
        ))
    } else {
        None
    }
}

/// Area centroid and total area of the region faces (the sea left out).
fn region_centroid(p: &[[f64; 3]], mesh: &RegionMesh, areas: &[f64]) -> ([f64; 2], f64) {
    let (mut cx, mut cy, mut s) = (0.0, 0.0, 0.0);
    for ((f, r), &a) in mesh.faces.iter().zip(&mesh.face_region).zip(areas) {
        if r.is_some() {
            for &v in f {
                cx += a * p[v as usize][0] / 3.0;
                cy += a * p[v as usize][1] / 3.0;
            }
            s += a;
        }
    }
    ([cx / s, cy / s], s)
}

/// Every region's rings through the mapped mesh: each ring vertex and the mesh vertices on its
/// edges, at their mapped positions (the image of the ring under the piecewise-linear map).
fn output_coordinates(
    set: &super::regions::RegionSet,
    mesh: &RegionMesh,
    positions: &[[f64; 3]],
) -> Vec<Vec<Polygon>> {
    set.regions
        .iter()
        .map(|r| {
            r.polygons
                .iter()
                .map(|rings| {
                    rings
                        .iter()
                        .map(|ring| {
                            mesh.dense_ring(ring)
                                .into_iter()
                                .map(|v| [positions[v][0], positions[v][1]])
                                .collect()
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sea_gets_the_mean_density_and_regions_their_values() {
        let pop = face_population(
            &[6.0, 2.0],
            &[Some(0), Some(0), Some(1), None],
            &[1.0, 2.0, 1.0, 4.0],
        );
        // Region 0: 6 over area 3 → 2 and 4; region 1: 2; sea: (8 / 4) × 4.
        assert_eq!(pop, vec![2.0, 4.0, 2.0, 8.0]);
    }
}
