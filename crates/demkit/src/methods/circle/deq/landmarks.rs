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
use crate::methods::iteration::{Flow, Measured, Moved, count_down};

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
/// nothing to improve (the last good map is kept), or after [`MAX_LEGS`] legs. The legs run on
/// the density-equalizing iteration ([`count_down`]) as the flow [`Legs`], one leg an iteration.
/// Returns the polishing's iterations and history; the landmarks not at their target are the
/// ones missed.
pub(crate) fn lead(
    faces: &[[u32; 3]],
    x: &mut [[f64; 3]],
    held: &[bool],
    n_region: usize,
    landmarks: &[u32],
    targets: &[[f64; 2]],
    polish: impl FnMut(&mut [[f64; 3]]) -> Result<Outcome>,
) -> Result<Outcome> {
    let mut flow = Legs {
        faces,
        held,
        movable: (0..x.len()).map(|v| v < n_region && !held[v]).collect(),
        landmarks,
        targets,
        polish,
        scale: 1.0,
        led: false,
        stopped: false,
        done: Outcome {
            iterations: 0,
            history: Vec::new(),
            converged: false,
        },
    };
    count_down(&mut flow, x, MAX_LEGS)?;
    Ok(flow.done)
}

/// LDEQ's legs as a flow of the density-equalizing iteration ([`count_down`]: `Step::Own`,
/// `Keep::Last`): the map is the positions; the stopping quantity (and merit) is the number of
/// landmarks not yet at their targets, below 1 when all are; one advance is one
/// leg, the landmarks' disks moved ([`move_vertices`]) and the map polished with the
/// landmarks pinned. A leg that cannot be taken halves the next one; when it would be shorter
/// than [`MIN_LEG_SCALE`], or the polishing fails (the map before the leg is then restored),
/// the flow cannot move the map any further and says so through its stopping quantity, which
/// ends the run. The polishing's iterations and histories are summed in `done`.
struct Legs<'a, P> {
    faces: &'a [[u32; 3]],
    held: &'a [bool],
    /// The vertices a landmark's disk may carry (the region's, off the loops).
    movable: Vec<bool>,
    landmarks: &'a [u32],
    targets: &'a [[f64; 2]],
    /// A few Newton steps with the landmarks pinned.
    polish: P,
    /// The next leg's length, as a share of the longest one.
    scale: f64,
    /// Whether a leg has been taken: the map as given has not been polished with the
    /// landmarks pinned, so it is not yet led even when they all sit at their targets.
    led: bool,
    /// Whether the last advance could not move the map (no leg left, or the polishing failed).
    stopped: bool,
    /// The polishing's iterations and histories so far.
    done: Outcome,
}

impl<P: FnMut(&mut [[f64; 3]]) -> Result<Outcome>> Flow for Legs<'_, P> {
    type Map = Vec<[f64; 3]>;
    type Data = ();

    /// The number of landmarks of `x` not at their targets; 0 once the flow has stopped
    /// moving, every landmark before the first leg.
    fn measure(&mut self, x: &Self::Map) -> Result<Measured<()>> {
        let away = if self.stopped {
            0
        } else if !self.led {
            self.landmarks.len().max(1)
        } else {
            self.landmarks
                .iter()
                .zip(self.targets)
                .filter(|&(&v, q)| x[v as usize][0] != q[0] || x[v as usize][1] != q[1])
                .count()
        };
        Ok(Measured {
            error: away as f64,
            merit: away as f64,
            data: (),
        })
    }

    /// One leg from `x`: `fraction` is the leg's share of the longest one when it was taken,
    /// 0 when it was not (then the map was only polished, or the flow stopped).
    fn advance(&mut self, x: &Self::Map, _m: &Measured<()>, _h: f64) -> Result<Moved<Self::Map>> {
        self.led = true;
        let mut moved = x.clone();
        let clearances = clearances(x, &self.movable, self.landmarks);
        let legs: Vec<[f64; 2]> = self
            .landmarks
            .iter()
            .zip(self.targets)
            .zip(&clearances)
            .map(|((&v, q), &rho)| next_leg(x[v as usize], *q, self.scale * rho))
            .collect();
        let movers = disk_movers(x, &self.movable, self.landmarks, &clearances, &legs);
        let mut fraction = self.scale;
        if !move_vertices(self.faces, &mut moved, self.held, &movers)? {
            fraction = 0.0;
            self.scale *= 0.5;
            if self.scale < MIN_LEG_SCALE {
                self.stopped = true;
                return Ok(Moved {
                    map: moved,
                    fraction: 0.0,
                });
            }
        }
        // Where the way is blocked a leg can leave the map with nothing left to improve.
        let Ok(step) = (self.polish)(&mut moved) else {
            self.stopped = true;
            return Ok(Moved {
                map: x.clone(),
                fraction: 0.0,
            });
        };
        self.done.iterations += step.iterations;
        self.done.history.extend(step.history);
        Ok(Moved {
            map: moved,
            fraction,
        })
    }
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
