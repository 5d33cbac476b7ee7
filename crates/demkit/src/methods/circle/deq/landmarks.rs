//! LDEQ's landmarks led to their targets without folding the map.
//!
//! A single vertex moved with the rest of the map following by harmonic extension drags a
//! spike: its one-ring is crushed long before it has gone a few edge lengths, and a smooth
//! displacement field crushes the slivers a density-equalizing map has. Instead each landmark
//! carries a disk of the map around it rigidly (no triangle inside deforms), the rest of the
//! map following by the harmonic extension with the current map's cotangent weights
//! (`rounding::move_vertices`, which moves thin triangles with their neighbours). The disk's
//! radius keeps it clear of the loops and of the other landmarks' disks, and one leg of the way
//! is at most [`LEG`] times that radius, so the squeeze a leg makes stays mild; between legs
//! the energy is minimised with the landmarks pinned, which spreads it out.

use super::newton::Outcome;
use super::rounding::move_vertices;
use crate::Result;

/// At most this many legs; a leg the map cannot take is halved, down to [`MIN_LEG_SCALE`] of
/// its length.
const MAX_LEGS: usize = 100;
const MIN_LEG_SCALE: f64 = 1.0 / 64.0;

/// A leg of a landmark's way is at most this share of its clearance.
pub(crate) const LEG: f64 = 0.4;

/// A landmark's disk reaches this share of its clearance.
const DISK: f64 = 0.4;

/// The clearance reaches at most this share of the way to the nearest loop vertex.
const TO_LOOPS: f64 = 0.8;

/// ... and this share of the way to the nearest other landmark (so the disks never overlap).
const TO_LANDMARKS: f64 = 0.45;

/// Leads the `landmarks` of the map `x` (region faces `faces`; `held`: the loops and hole
/// fillings, which stay; the region's vertices are the first `n_region`) to their `targets`
/// leg by leg, calling `polish` (a few Newton steps with the landmarks pinned) after each.
/// Stops when all are there, when a leg cannot be taken even shortened, or when `polish` finds
/// nothing to improve (the last good map is kept). Returns the polishing's iterations and
/// history; the landmarks not at their target are the ones missed.
pub(crate) fn lead(
    faces: &[[u32; 3]],
    x: &mut [[f64; 3]],
    held: &[bool],
    n_region: usize,
    landmarks: &[u32],
    targets: &[[f64; 2]],
    mut polish: impl FnMut(&mut [[f64; 3]]) -> Result<Outcome>,
) -> Result<Outcome> {
    let movable: Vec<bool> = (0..x.len()).map(|v| v < n_region && !held[v]).collect();
    let mut done = Outcome {
        iterations: 0,
        history: Vec::new(),
        converged: false,
    };
    let mut before = x.to_vec();
    let mut scale = 1.0;
    for _ in 0..MAX_LEGS {
        let clearances = clearances(x, &movable, landmarks);
        let legs: Vec<[f64; 2]> = landmarks
            .iter()
            .zip(targets)
            .zip(&clearances)
            .map(|((&v, q), &rho)| next_leg(x[v as usize], *q, scale * rho))
            .collect();
        let movers = disk_movers(x, &movable, landmarks, &clearances, &legs);
        before.copy_from_slice(x);
        if !move_vertices(faces, x, held, &movers)? {
            scale *= 0.5;
            if scale < MIN_LEG_SCALE {
                break;
            }
        }
        // Where the way is blocked a leg can leave the map with nothing left to improve.
        let Ok(step) = polish(x) else {
            x.copy_from_slice(&before);
            break;
        };
        done.iterations += step.iterations;
        done.history.extend(step.history);
        let there = landmarks
            .iter()
            .zip(targets)
            .all(|(&v, q)| x[v as usize][0] == q[0] && x[v as usize][1] == q[1]);
        if there {
            break;
        }
    }
    Ok(done)
}

/// Each landmark's clearance in the map `x`: a share of the distance to the nearest vertex
/// `movable` holds still (the loops, the hole fillings) and to the nearest other landmark.
pub(crate) fn clearances(x: &[[f64; 3]], movable: &[bool], landmarks: &[u32]) -> Vec<f64> {
    let dist = |a: [f64; 3], b: [f64; 3]| (a[0] - b[0]).hypot(a[1] - b[1]);
    landmarks
        .iter()
        .map(|&v| {
            let p = x[v as usize];
            let to_loops = x
                .iter()
                .zip(movable)
                .filter(|(_, m)| !**m)
                .map(|(q, _)| dist(p, *q))
                .fold(f64::INFINITY, f64::min);
            let to_landmarks = landmarks
                .iter()
                .filter(|&&w| w != v)
                .map(|&w| dist(p, x[w as usize]))
                .fold(f64::INFINITY, f64::min);
            (TO_LOOPS * to_loops).min(TO_LANDMARKS * to_landmarks)
        })
        .collect()
}

/// The next leg of each landmark's way to its target: the target itself when it is within
/// [`LEG`] clearances, otherwise that far towards it.
pub(crate) fn next_leg(p: [f64; 3], target: [f64; 2], clearance: f64) -> [f64; 2] {
    let c = [target[0] - p[0], target[1] - p[1]];
    let len = c[0].hypot(c[1]);
    let reach = LEG * clearance;
    if len <= reach {
        target
    } else {
        [p[0] + c[0] * reach / len, p[1] + c[1] * reach / len]
    }
}

/// The vertices that move with each landmark, with where they go: every vertex `movable`
/// allows within [`DISK`] clearances of landmark `k`, shifted by the landmark's way to `legs[k]`.
pub(crate) fn disk_movers(
    x: &[[f64; 3]],
    movable: &[bool],
    landmarks: &[u32],
    clearances: &[f64],
    legs: &[[f64; 2]],
) -> Vec<(u32, [f64; 2])> {
    let mut movers = Vec::new();
    for ((&w, &rho), q) in landmarks.iter().zip(clearances).zip(legs) {
        let p = x[w as usize];
        let c = [q[0] - p[0], q[1] - p[1]];
        movers.push((w, *q));
        for (v, y) in x.iter().enumerate() {
            if v != w as usize && movable[v] && (y[0] - p[0]).hypot(y[1] - p[1]) < DISK * rho {
                movers.push((v as u32, [y[0] + c[0], y[1] + c[1]]));
            }
        }
    }
    movers
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_leg_stops_short_of_a_far_target_and_reaches_a_near_one() {
        let p = [0.0, 0.0, 0.0];
        assert_eq!(next_leg(p, [0.1, 0.0], 1.0), [0.1, 0.0]);
        let leg = next_leg(p, [3.0, 4.0], 1.0);
        assert!((leg[0] - 0.24).abs() < 1e-15 && (leg[1] - 0.32).abs() < 1e-15);
    }

    #[test]
    fn clearance_is_limited_by_the_loops_and_the_other_landmarks() {
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, -3.0, 0.0],
        ];
        let movable = [true, false, true, true];
        let c = clearances(&x, &movable, &[0, 2]);
        assert!((c[0] - 0.45 * 0.5).abs() < 1e-15);
        let c = clearances(&x, &movable, &[0, 3]);
        assert!((c[0] - 0.8).abs() < 1e-15);
    }

    #[test]
    fn a_landmarks_disk_moves_rigidly_and_held_vertices_stay_out() {
        let x = [
            [0.0, 0.0, 0.0],
            [0.1, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.0, 0.1, 0.0],
        ];
        let movable = [true, true, true, false];
        let movers = disk_movers(&x, &movable, &[0], &[1.0], &[[0.2, 0.0]]);
        assert_eq!(
            movers,
            vec![(0, [0.2, 0.0]), (1, [0.30000000000000004, 0.0])]
        );
    }
}
