//! The translation of a flat torus map along `v` that best matches face areas on the target
//! torus.
//!
//! A map onto the flat torus can be translated freely, but `φ` (8) is not an isometry: a face at
//! height `v` has area `(1 + (r/R) cos(v/r))` times its flat area on the torus, the inner
//! equator (`v = ±πr`) shrinking faces by `(R − r)/R` and the outer one (`v = 0`) stretching
//! them by `(R + r)/R`. Translating along `u` changes nothing (rotational symmetry); the
//! translation along `v` is chosen to minimise the paper's area distortion (27),
//! `mean |log((a_f / Σa) / (A_f / ΣA))|`, between the prescribed shares `a_f` (the source face
//! areas for the initial map) and the torus areas `A_f`, with `A_f` taken at the face's
//! centroid height.

use crate::geometry::torus::{FlatTorusMap, Torus};
use std::f64::consts::TAU;

/// Shifts tried over one period before the golden-section refinement.
const SAMPLES: usize = 64;
/// Golden-section steps (each shrinks the bracket by 0.618).
const REFINEMENTS: usize = 40;

/// The shift of `v` in `[0, 2πr)` minimising the area distortion between `target` (one
/// positive value per face; any scale) and the torus areas of `map` translated by it (see the
/// module documentation). 0 when `target` is unusable (wrong length, no positive total).
pub fn area_balanced_shift(
    map: &FlatTorusMap,
    faces: &[[u32; 3]],
    torus: &Torus,
    target: &[f64],
) -> f64 {
    let period = torus.periods();
    let total: f64 = target.iter().sum();
    if target.len() != faces.len() || !(total > 0.0 && total.is_finite()) {
        return 0.0;
    }
    let ratio = torus.minor / torus.major;
    // Per face: log of its target share, its flat area, and cos, sin of its centroid angle.
    let faces_data: Vec<(f64, f64, f64, f64)> = (0..faces.len())
        .map(|f| {
            let c = map.corners(faces, f, period);
            let flat = 0.5
                * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                    - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]));
            let angle = (c[0][1] + c[1][1] + c[2][1]) / (3.0 * torus.minor);
            let (s, co) = angle.sin_cos();
            ((target[f] / total).ln(), flat, co, s)
        })
        .collect();
    let distortion = |shift: f64| -> f64 {
        let (st, ct) = (shift / torus.minor).sin_cos();
        // cos(angle + t) = cos·cos t − sin·sin t.
        let area =
            |&(_, flat, c, s): &(f64, f64, f64, f64)| flat * (1.0 + ratio * (c * ct - s * st));
        let sum: f64 = faces_data.iter().map(area).sum();
        let log_sum = sum.ln();
        faces_data
            .iter()
            .map(|d| (d.0 - (area(d).ln() - log_sum)).abs())
            .sum::<f64>()
    };
    // The samples over one period, then the golden-section refinement.
    let step = TAU * torus.minor / SAMPLES as f64;
    let (t, _) = crate::optimize::sampled_golden_section(
        distortion,
        0.0,
        step * (SAMPLES - 1) as f64,
        SAMPLES,
        REFINEMENTS,
    );
    t.rem_euclid(period[1])
}
