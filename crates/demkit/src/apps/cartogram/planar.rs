//! The planar cartogram by the flow of Gastner, Seguy & More (2018): the regions' densities
//! (value / area, the sea at the mean density) are rasterized on a grid around the map
//! ([`super::raster`]), the flow that takes them linearly to the mean is solved in closed
//! form ([`super::flow`]), and every vertex moves with it ([`super::advect`]). Rounds repeat this
//! from the map reached, with densities from the current areas, until every region's share of
//! the area is within [`Config::tolerance`] of its share of the values.
//!
//! All regions move over one shared vertex list, so a border shared by two regions stays
//! shared; the flow's map is one-to-one, so regions cannot overlap. Long edges get extra
//! vertices before each round ([`super::densify`]), so that straight edges follow the map.

use super::advect::{advect, replay};
use super::crossings::crossing_edges;
use super::densify::split_edges;
use super::flow::Flow;
use super::raster::{self, IndexRings, polygon_area_centroid};
use super::regions::RegionSet;
use super::rings::{bbox, map_polygons};
use super::{Cartogram, Config, Polygon, finish, share_errors, unit_values};
use crate::methods::{Progress, ProgressFn, StopReason};
use crate::{Error, Result};
use std::collections::HashSet;
use std::time::Instant;

/// The sea around the map on every side, as a fraction of the map's larger extent.
const MARGIN: f64 = 0.25;

/// The grid's shorter side is a multiple of its longer side divided by this.
const SIDE_STEP: usize = 16;

/// The grid may be refined, when the rounds stall, up to this many times the grid asked for.
const GRID_GROWTH: usize = 2;

/// The rounds stop (or the grid is refined) when this many in a row have not lowered the
/// worst error.
const STALL_ROUNDS: usize = 4;

/// The first round's density is blurred by a diffusion for this time (cells², a Gaussian of
/// about √(2·BLUR) cells), each later round's by half the previous one's: the sharp steps of
/// density between regions would otherwise ask for tiny first steps.
const BLUR: f64 = 4.0;

/// How many times a round's flow is run again with the edges that crossed split.
const REFINEMENTS: usize = 8;

/// The parts each crossing edge is split into before the flow is run again.
const REFINE_PARTS: usize = 4;

/// Accepted integration steps per round when [`Config::max_iter`] is not set.
const DEFAULT_STEPS: usize = 10_000;

/// Refuses a grid side that is not a power of two in [16, 8192].
pub fn check_grid(grid: usize) -> Result<()> {
    if !(16..=8192).contains(&grid) || !grid.is_power_of_two() {
        return Err(Error::Argument(format!(
            "grid must be a power of two from 16 to 8192, got {grid}"
        )));
    }
    Ok(())
}

/// The regions' areas (holes subtracted) over `points`.
pub fn region_areas(points: &[[f64; 2]], rings: &[IndexRings]) -> Vec<f64> {
    rings
        .iter()
        .map(|polys| {
            polys
                .iter()
                .map(|p| polygon_area_centroid(points, p).0)
                .sum()
        })
        .collect()
}

/// Total area and area centroid of the regions.
fn centroid(points: &[[f64; 2]], rings: &[IndexRings]) -> (f64, [f64; 2]) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for p in rings.iter().flatten() {
        let (s, c) = polygon_area_centroid(points, p);
        a += s;
        cx += s * c[0];
        cy += s * c[1];
    }
    if a > 0.0 {
        (a, [cx / a, cy / a])
    } else {
        (0.0, [0.0, 0.0])
    }
}

/// The worst share error over the regions that count (see [`super::counts`]).
fn worst(errors: &[f64], targets: &[f64]) -> f64 {
    errors
        .iter()
        .zip(targets)
        .filter(|(_, t)| super::counts(**t))
        .fold(0.0f64, |m, (e, _)| m.max(e.abs()))
}

/// The largest gain of [`update_gain`].
const MAX_GAIN: f64 = 4.0;

/// A region whose share is within this fraction of the accuracy asked for
/// ([`Config::tolerance`]) of its target gets no gain.
const NO_GAIN_WITHIN: f64 = 0.5;

/// Adapts every region's gain, the exponent its density contrast is raised to in a round: a
/// round moves a region's share only part of the way to its target when the region spans few
/// cells, or sits between much denser neighbours; the next round asks for correspondingly
/// more (the geometric mean of its gain and the inverse of the fraction achieved, within
/// [1, [`MAX_GAIN`]]; back to 1 after a round that went past the target). At the target the
/// contrast is 1 whatever the gain, so the fixed point is the cartogram's.
fn update_gain(
    gain: &mut [f64],
    targets: &[f64],
    (before, after): (&[f64], &[f64]),
    tolerance: f64,
) {
    let min_wanted = NO_GAIN_WITHIN * tolerance;
    let (tb, ta): (f64, f64) = (before.iter().sum(), after.iter().sum());
    for i in 0..gain.len() {
        let (sb, sa) = (before[i] / tb, after[i] / ta);
        if !(sb > 0.0 && sa > 0.0 && targets[i] > 0.0) {
            continue;
        }
        let wanted = (targets[i] / sb).ln();
        let achieved = (sa / sb).ln();
        if wanted.abs() < min_wanted {
            gain[i] = 1.0;
            continue;
        }
        if (targets[i] / sa).ln() * wanted < 0.0 {
            // Past the target: back to no gain.
            gain[i] = 1.0;
            continue;
        }
        let fraction = achieved / (wanted * gain[i]);
        let next = if fraction > 0.0 {
            (1.0 / fraction).clamp(1.0, MAX_GAIN)
        } else {
            1.0
        };
        gain[i] = (gain[i] * next).sqrt();
    }
}

/// The least number at least `n` whose prime factors are 2, 3 and 5 only (289 → 300; at
/// most 11 % above `n` from 100 on).
fn smooth_at_least(n: usize) -> usize {
    let smooth = |mut m: usize| {
        for p in [2, 3, 5] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        m == 1
    };
    (n.max(1)..).find(|&m| smooth(m)).unwrap_or(n)
}

/// What every round of one run shares.
#[derive(Clone, Copy)]
struct Setup {
    /// Cells along the grid's longer side.
    grid: usize,
    /// Accepted integration steps per round.
    max_steps: usize,
    /// The lines of the grid's lower and upper walls, when fixed (see [`flow`]).
    walls: Option<[f64; 2]>,
}

/// One round of the flow: rasterize, diffuse, move `points` (in place), the density contrast
/// raised to `gain` after a blur of `blur`. `clean` says on entry whether the map is known to
/// have no crossing edge, and on return whether the round ended with none. Returns the
/// integration steps taken and the grid.
fn round(
    points: &mut Vec<[f64; 2]>,
    rings: &mut [IndexRings],
    values: &[f64],
    setup: &Setup,
    (blur, gain): (f64, &[f64]),
    clean: &mut bool,
) -> (usize, [usize; 2]) {
    let Setup {
        grid,
        max_steps,
        walls,
    } = *setup;
    let (lo, hi) = bbox(points.iter().copied());
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let long = w.max(h);
    let margin = MARGIN * long;
    let mut cell = (long + 2.0 * margin) / grid as f64;
    let step = (grid / SIDE_STEP).max(1);
    let mut origin_y = None;
    if let Some([y0, y1]) = walls {
        // The grid's lower and upper walls on the given lines, the cell a whole fraction
        // of the distance between them: a number of rows with no prime factor above 5, for
        // which the cosine transforms are fastest (the world's 289 = 17² rows took 18 % of
        // the globe's run in its transforms).
        let rows = smooth_at_least(((y1 - y0) / cell).ceil().max(1.0) as usize).min(grid) as f64;
        cell = (y1 - y0) / rows;
        origin_y = Some((y0, rows as usize));
    }
    let side = |e: f64| {
        let n = ((e + 2.0 * margin) / cell).ceil() as usize;
        (n.div_ceil(step) * step).clamp(step, grid)
    };
    let nx = side(w);
    let ny = origin_y.map_or_else(|| side(h), |(_, rows)| rows);
    let origin = [
        0.5 * (lo[0] + hi[0]) - 0.5 * nx as f64 * cell,
        origin_y.map_or_else(
            || 0.5 * (lo[1] + hi[1]) - 0.5 * ny as f64 * cell,
            |(y0, _)| y0,
        ),
    ];
    for p in points.iter_mut() {
        *p = [(p[0] - origin[0]) / cell, (p[1] - origin[1]) / cell];
    }
    super::densify::densify(points, rings, 1.0);
    let areas = region_areas(points, rings);
    let total_value: f64 = values.iter().sum();
    let total_area: f64 = areas.iter().sum();
    let sea = total_value / total_area;
    let density: Vec<f64> = values
        .iter()
        .zip(&areas)
        .zip(gain)
        .map(|((v, a), g)| {
            if *a > 0.0 {
                sea * (v / a / sea).powf(*g)
            } else {
                sea
            }
        })
        .collect();
    let rho = raster::density(points, rings, &density, sea, nx, ny);
    let flow = Flow::new(&rho, nx, ny, blur);
    let mut start = points.clone();
    // A map known to have no crossing edge keeps none when its edges are split on
    // themselves (densify): no need to look for them again.
    let crossing_before = if *clean {
        HashSet::new()
    } else {
        crossing_edges(points, rings)
    };
    let integration = advect(&flow, nx, ny, points, max_steps);
    *clean = false;
    for _ in 0..REFINEMENTS {
        let mut crossing = crossing_edges(points, rings);
        let none = crossing.is_empty();
        // Crossings the round started with are not the flow's to mend.
        crossing.retain(|e| !crossing_before.contains(e));
        if crossing.is_empty() {
            *clean = none;
            break;
        }
        // Straight edges between moved vertices crossed where the flow bends them more than
        // they are apart: those edges split, and the new vertices taken by the same steps.
        let old = start.len();
        split_edges(&mut start, rings, &crossing, REFINE_PARTS);
        let mut added = start[old..].to_vec();
        replay(&flow, nx, ny, &mut added, &integration.schedule);
        points.extend(added);
    }
    for p in points.iter_mut() {
        *p = [origin[0] + p[0] * cell, origin[1] + p[1] * cell];
    }
    (integration.steps, [nx, ny])
}

/// What the rounds of the flow reached: the moved vertices and the rings over them.
pub struct Flowed {
    /// The vertices (the input's first, then those added on long edges).
    pub points: Vec<[f64; 2]>,
    /// Every region's polygons → rings → indices into `points`.
    pub rings: Vec<IndexRings>,
    /// The output as coordinates, in the regions' ring structure.
    pub coordinates: Vec<Vec<Polygon>>,
    /// How the run went (no mesh: `mesh_faces` 0, `mesh_vertices` the vertices).
    pub run: super::Run,
}

/// Runs rounds of the flow on regions given as `rings` over `points` with `values` (all
/// positive), in any plane coordinates, and returns the best round (the lowest worst share
/// error of the regions that count, see [`super::counts`]), scaled so that the regions'
/// total area is the input's and moved so that their area centroid is the input's.
///
/// Rounds run while the worst error is above `config.tolerance`, at most `config.rounds` of
/// them, none started after `config.time_limit`, and until [`STALL_ROUNDS`] in a row have
/// not improved on the best.
///
/// With `walls` = `[y0, y1]`, the grid's lower and upper walls lie on those lines in every
/// round, which the flow does not cross (the poles of the globe's projection), and the result
/// is neither scaled nor moved.
///
/// Errors: a grid side refused by [`check_grid`].
pub fn flow(
    points: Vec<[f64; 2]>,
    rings: Vec<IndexRings>,
    values: &[f64],
    config: &Config,
    walls: Option<[f64; 2]>,
    progress: ProgressFn,
) -> Result<Flowed> {
    let t0 = Instant::now();
    check_grid(config.grid)?;
    let values = unit_values(values);
    let total: f64 = values.iter().sum();
    let targets: Vec<f64> = values.iter().map(|v| v / total).collect();
    let (mut points, mut rings) = (points, rings);
    let (a_in, c_in) = centroid(&points, &rings);
    let mut setup = Setup {
        grid: config.grid,
        max_steps: config.max_iter.unwrap_or(DEFAULT_STEPS).max(1),
        walls,
    };
    let rounds_cap = config.rounds.max(1);
    let mut best: Option<(f64, Vec<[f64; 2]>, Vec<IndexRings>)> = None;
    let (mut since_best, mut steps, mut rounds) = (0, 0, 0);
    let mut grid_used = [0, 0];
    let mut stop_reason = StopReason::MaxIter;
    let mut notes = Vec::new();
    let mut gain = vec![1.0; values.len()];
    // Whether the map is known to have no crossing edge (see `round`).
    let mut clean = false;
    loop {
        let errors = share_errors(&values, &region_areas(&points, &rings));
        let w = worst(&errors, &targets);
        progress(Progress {
            iteration: rounds,
            max_iter: rounds_cap,
            error: w,
        });
        if best.as_ref().is_none_or(|b| w < b.0) {
            best = Some((w, points.clone(), rings.clone()));
            since_best = 0;
        } else {
            since_best += 1;
        }
        if w <= config.tolerance {
            stop_reason = StopReason::Tolerance;
            break;
        }
        if since_best >= STALL_ROUNDS && setup.grid < config.grid * GRID_GROWTH && setup.grid < 8192
        {
            // Regions of a few cells stall on the grid's resolution: on from the best round
            // with cells half as wide.
            notes.push(format!(
                "the rounds stopped improving on the grid of {}; continued from the best round \
                 on a grid of {}",
                setup.grid,
                2 * setup.grid
            ));
            setup.grid *= 2;
            since_best = 0;
            if let Some((_, p, r)) = &best {
                points.clone_from(p);
                rings.clone_from(r);
                clean = false;
            }
        } else if since_best >= STALL_ROUNDS {
            stop_reason = StopReason::Stationary;
            notes.push(format!(
                "the rounds stopped improving: {STALL_ROUNDS} rounds in a row without a lower \
                 worst error"
            ));
            break;
        }
        if rounds >= rounds_cap {
            notes.push(format!("the round limit ({rounds_cap}) was reached"));
            break;
        }
        if let Some(limit) = config.time_limit
            && t0.elapsed().as_secs_f64() >= limit
        {
            notes.push(format!("the time limit ({limit} s) was reached"));
            break;
        }
        let blur = BLUR * 0.5f64.powi(rounds as i32);
        let before = region_areas(&points, &rings);
        let (s, g) = round(
            &mut points,
            &mut rings,
            &values,
            &setup,
            (blur, &gain),
            &mut clean,
        );
        update_gain(
            &mut gain,
            &targets,
            (&before, &region_areas(&points, &rings)),
            config.tolerance,
        );
        steps += s;
        rounds += 1;
        grid_used = g;
    }
    let Some((_, mut points, rings)) = best else {
        return Err(Error::Numerical("the cartogram ran no round".into()));
    };
    let (a, c) = centroid(&points, &rings);
    if walls.is_none() && a > 0.0 && a_in > 0.0 {
        let k = (a_in / a).sqrt();
        for p in points.iter_mut() {
            *p = [c_in[0] + k * (p[0] - c[0]), c_in[1] + k * (p[1] - c[1])];
        }
    }
    let coordinates: Vec<Vec<Polygon>> = rings
        .iter()
        .map(|polys| map_polygons(polys, |v| points[v]))
        .collect();
    let run = super::Run {
        iterations: steps,
        rounds,
        stop_reason,
        mesh_vertices: points.len(),
        mesh_faces: 0,
        grid: grid_used,
        flipped_triangles: 0,
        notes,
        time_s: t0.elapsed().as_secs_f64(),
    };
    Ok(Flowed {
        points,
        rings,
        coordinates,
        run,
    })
}

/// Computes the planar cartogram of `set` (coordinates in the plane) with [`flow`], in the
/// set's normalised frame, and takes the result back to input units.
///
/// Errors: a grid side refused by [`check_grid`]; the errors of [`finish`].
pub fn run(
    set: &RegionSet,
    config: &Config,
    path: &str,
    progress: ProgressFn,
) -> Result<Cartogram> {
    let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
    let rings: Vec<IndexRings> = set.regions.iter().map(|r| r.polygons.clone()).collect();
    let f = flow(set.points.clone(), rings, &values, config, None, progress)?;
    finish(set, f.coordinates, f.run, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 4 block of unit squares of value 1 but one of 1e-3, as rings over shared points.
    fn one_small() -> (Vec<[f64; 2]>, Vec<IndexRings>, Vec<f64>) {
        let n = 4;
        let points: Vec<[f64; 2]> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64]))
            .collect();
        let at = |i: usize, j: usize| j * (n + 1) + i;
        let mut rings = Vec::new();
        let mut values = Vec::new();
        for j in 0..n {
            for i in 0..n {
                rings.push(vec![vec![vec![
                    at(i, j),
                    at(i + 1, j),
                    at(i + 1, j + 1),
                    at(i, j + 1),
                ]]]);
                values.push(if (i, j) == (1, 1) { 1e-3 } else { 1.0 });
            }
        }
        (points, rings, values)
    }

    #[test]
    fn smooth_numbers_of_rows() {
        assert_eq!(smooth_at_least(289), 300);
        assert_eq!(smooth_at_least(1), 1);
        assert_eq!(smooth_at_least(0), 1);
        assert_eq!(smooth_at_least(97), 100);
        assert_eq!(smooth_at_least(1024), 1024);
    }

    #[test]
    fn a_stalled_run_goes_on_at_twice_the_grid_and_no_further() {
        let (points, rings, values) = one_small();
        // An accuracy no grid reaches: the rounds run until they stall.
        let config = Config {
            grid: 16,
            rounds: 1000,
            tolerance: 1e-12,
            ..Config::default()
        };
        let f = flow(points, rings, &values, &config, None, &mut |_| {}).unwrap();
        // The rounds stall on 16 cells, go on at 32, stall again and stop there.
        assert!(
            f.run.notes.iter().any(|n| n.contains("on a grid of 32")),
            "{:?}",
            f.run.notes
        );
        assert_eq!(f.run.grid[0], 32);
        assert!(!f.run.notes.iter().any(|n| n.contains("on a grid of 64")));
    }
}
