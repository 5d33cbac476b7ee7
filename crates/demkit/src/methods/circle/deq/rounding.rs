//! Moving chosen vertices of a planar map to given points without folding it: the second step
//! of DEQ's initial map (the holes made round) and the landmarks of LDEQ sent to their
//! targets.
//!
//! The chosen vertices move straight towards their targets; the rest of the map follows by the
//! harmonic extension of their displacement (cotangent weights of the current map, which carry
//! a locally affine displacement affinely, so thin triangles move with their neighbours), with
//! every other boundary vertex held. The move is taken as far as no triangle is squeezed more
//! than halfway to collapse (the DEM iteration's safeguard, `planar_diffusion::collapse_time`)
//! and recomputed from where it got to, until the vertices arrive.

use super::circles::Circle;
use crate::Result;
use crate::fem::{DirichletSystem, cotangent_weights};
use crate::geometry::segment::polygon_distance;
use crate::methods::disk::planar_diffusion::collapse_time;
use rayon::prelude::*;

/// Rounds of harmonic extension at most.
const MAX_ROUNDS: usize = 200;

/// A round that can go less than this fraction of the remaining way is the last: the map is
/// stuck (a target beyond the boundary, say), and going on would only crush triangles.
const MIN_PROGRESS: f64 = 1e-3;

/// Moves the vertices `movers` of the planar map `x` (faces `faces`) to their targets, holding
/// the vertices where `held` is true (and every vertex no face uses). Returns true when all
/// arrived; otherwise they stay as far along as the map allowed.
pub(crate) fn move_vertices(
    faces: &[[u32; 3]],
    x: &mut [[f64; 3]],
    held: &[bool],
    movers: &[(u32, [f64; 2])],
) -> Result<bool> {
    let n = x.len();
    let mut fixed = vec![true; n];
    for f in faces {
        for &v in f {
            fixed[v as usize] = held[v as usize];
        }
    }
    for &(v, _) in movers {
        fixed[v as usize] = true;
    }
    let system = DirichletSystem::new(n, faces, &fixed)?;
    for _ in 0..MAX_ROUNDS {
        let mut displacement = vec![[0.0; 3]; n];
        for &(v, q) in movers {
            let p = x[v as usize];
            displacement[v as usize] = [q[0] - p[0], q[1] - p[1], 0.0];
        }
        let d = system.solve(&cotangent_weights(x, faces), &displacement)?;
        let t = faces
            .par_iter()
            .map(|f| {
                collapse_time(
                    f.map(|v| x[v as usize]),
                    f.map(|v| [d[v as usize][0], d[v as usize][1]]),
                )
            })
            .reduce(|| f64::INFINITY, f64::min);
        let tau = (0.5 * t).min(1.0);
        if !(tau > MIN_PROGRESS) {
            return Ok(false);
        }
        // Held vertices have zero displacement; the movers' is the way to their targets.
        let before = x.to_vec();
        for (p, s) in x.iter_mut().zip(&d) {
            p[0] += tau * s[0];
            p[1] += tau * s[1];
        }
        if crate::geometry::count_nonpositive(x, faces) > 0 {
            // Only rounding can fold a triangle this close to collapse: stop before it.
            x.copy_from_slice(&before);
            return Ok(false);
        }
        if tau == 1.0 {
            for &(v, q) in movers {
                x[v as usize] = [q[0], q[1], 0.0];
            }
            return Ok(true);
        }
    }
    Ok(false)
}

/// How large a hole's circle is made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Size {
    /// The polygon's area: the hole keeps its size.
    Area,
    /// Nine tenths of the distance from the centre to the polygon's nearest edge: the circle
    /// lies inside the polygon, so the loop only moves into its own hole (for a hole whose
    /// area circle would reach another hole or the outer loop).
    Inside,
}

/// The circle each hole of the planar map `x` is made: centred at the centroid of the hole's
/// polygon when the polygon is star-shaped around it (else at `centre`, the fan centre it is
/// star-shaped around), of the given `size`; every loop vertex goes radially onto it.
pub(crate) fn round_targets(
    x: &[[f64; 3]],
    lp: &[u32],
    centre: [f64; 2],
    size: Size,
) -> (Circle, Vec<(u32, [f64; 2])>) {
    let (area, centroid) = polygon_area_centroid(x, lp);
    let center = if star_shaped(x, lp, centroid) {
        centroid
    } else {
        centre
    };
    let radius = match size {
        Size::Area => (area.abs() / std::f64::consts::PI).sqrt(),
        Size::Inside => {
            let corners = lp.iter().map(|&v| [x[v as usize][0], x[v as usize][1]]);
            0.9 * polygon_distance(corners, center)
        }
    };
    let circle = Circle { center, radius };
    let targets = lp
        .iter()
        .map(|&v| {
            let q = circle.project(x[v as usize]);
            (v, [q[0], q[1]])
        })
        .collect();
    (circle, targets)
}

/// Signed area and centroid of the polygon `lp` in `x`.
fn polygon_area_centroid(x: &[[f64; 3]], lp: &[u32]) -> (f64, [f64; 2]) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..lp.len() {
        let p = x[lp[k] as usize];
        let q = x[lp[(k + 1) % lp.len()] as usize];
        let c = p[0] * q[1] - q[0] * p[1];
        a += 0.5 * c;
        cx += (p[0] + q[0]) * c / 6.0;
        cy += (p[1] + q[1]) * c / 6.0;
    }
    (a, [cx / a, cy / a])
}

/// True when every edge of the polygon `lp` turns the same way around `c` (so the polygon is
/// star-shaped around it).
fn star_shaped(x: &[[f64; 3]], lp: &[u32], c: [f64; 2]) -> bool {
    let sign = |k: usize| {
        let p = x[lp[k] as usize];
        let q = x[lp[(k + 1) % lp.len()] as usize];
        (p[0] - c[0]) * (q[1] - c[1]) - (p[1] - c[1]) * (q[0] - c[0])
    };
    let first = sign(0);
    (0..lp.len()).all(|k| sign(k) * first > 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;

    #[test]
    fn a_vertex_moves_to_its_target_and_nothing_folds() {
        let (pos, faces, boundary) = grid(8, 0.2);
        let mut x = pos.clone();
        let centre = (0..pos.len())
            .find(|&v| (pos[v][0] - 0.5).abs() < 0.07 && (pos[v][1] - 0.5).abs() < 0.07)
            .unwrap() as u32;
        let target = [x[centre as usize][0] + 0.2, x[centre as usize][1] + 0.1];
        let reached = move_vertices(&faces, &mut x, &boundary, &[(centre, target)]).unwrap();
        assert!(reached);
        assert_eq!(x[centre as usize][..2], target);
        assert_eq!(crate::geometry::count_nonpositive(&x, &faces), 0);
        for (v, &b) in boundary.iter().enumerate() {
            if b {
                assert_eq!(x[v], pos[v]);
            }
        }
    }

    #[test]
    fn a_target_beyond_the_boundary_is_not_reached() {
        let (pos, faces, boundary) = grid(6, 0.0);
        let mut x = pos.clone();
        let v = (0..pos.len()).find(|&v| !boundary[v]).unwrap() as u32;
        let reached = move_vertices(&faces, &mut x, &boundary, &[(v, [3.0, 3.0])]).unwrap();
        assert!(!reached);
        assert_eq!(crate::geometry::count_nonpositive(&x, &faces), 0);
    }

    #[test]
    fn a_square_hole_becomes_a_circle_of_its_area() {
        let x: Vec<[f64; 3]> = [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]]
            .iter()
            .map(|p| [p[0] + 3.0, p[1], 0.0])
            .collect();
        // Clockwise, as a hole's loop runs.
        let lp = [0u32, 3, 2, 1];
        let (c, targets) = round_targets(&x, &lp, [0.0, 0.0], Size::Area);
        assert!((c.center[0] - 3.0).abs() < 1e-12 && c.center[1].abs() < 1e-12);
        assert!((c.radius - (4.0 / std::f64::consts::PI).sqrt()).abs() < 1e-12);
        for (v, q) in targets {
            let p = x[v as usize];
            // Radially: the target lies on the ray from the centre through the vertex.
            let cross = (p[0] - 3.0) * q[1] - p[1] * (q[0] - 3.0);
            assert!(cross.abs() < 1e-12);
        }
        let (inside, _) = round_targets(&x, &lp, [0.0, 0.0], Size::Inside);
        assert!((inside.radius - 0.9).abs() < 1e-12);
    }
}
