//! Elementary triangle geometry: areas, normals, corner cotangents, local orthonormal frames.
//! Positions are `[f64; 3]` everywhere (planar maps use z = 0), so every operator has one
//! implementation for surfaces and for planar maps.

pub mod ellipsoid;
pub(crate) mod grid;
pub mod locate;
mod plane;
pub mod rotation;
pub mod segment;
pub mod sphere;
pub mod torus;
mod vec3;

pub use plane::{PlaneFrame, planar_frame};

pub use vec3::{add, cross, dot, norm, scale, sub};

use rayon::prelude::*;

/// The axis-aligned bounding box of points: (least, largest) coordinates; (+∞, −∞) for no points.
pub fn bounding_box(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    bounds(points.iter().copied())
}

/// The axis-aligned bounding box of points in any dimension: (least, largest) coordinates;
/// (+∞, −∞) for no points.
pub(crate) fn bounds<const N: usize>(
    points: impl IntoIterator<Item = [f64; N]>,
) -> ([f64; N], [f64; N]) {
    let mut lo = [f64::INFINITY; N];
    let mut hi = [f64::NEG_INFINITY; N];
    for p in points {
        for d in 0..N {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    (lo, hi)
}

/// The length of the diagonal of the points' bounding box (the scale of "within 1e-6 of the
/// surface" and of registration errors); 0 for fewer than one point.
pub fn bounding_box_diagonal(points: &[[f64; 3]]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let (lo, hi) = bounding_box(points);
    norm(sub(hi, lo))
}

/// Area of the triangle (a, b, c) in R³ (unsigned): ½ |(b − a) × (c − a)|.
#[inline]
pub fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

/// Signed area of the planar triangle (a, b, c) using x and y only: positive when
/// counter-clockwise.
pub fn signed_area_2d(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Unsigned areas of all faces (in parallel).
pub fn face_areas(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    per_face(positions, faces, triangle_area)
}

/// Signed planar areas of all faces (x, y only; positive when counter-clockwise).
pub fn signed_areas_2d(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    per_face(positions, faces, signed_area_2d)
}

/// `area` of every face's corners (in parallel; generic, so that `area` is inlined into the
/// loop instead of called through a pointer per face).
fn per_face<A>(positions: &[[f64; 3]], faces: &[[u32; 3]], area: A) -> Vec<f64>
where
    A: Fn([f64; 3], [f64; 3], [f64; 3]) -> f64 + Sync,
{
    faces
        .par_iter()
        .map(|f| {
            area(
                positions[f[0] as usize],
                positions[f[1] as usize],
                positions[f[2] as usize],
            )
        })
        .collect()
}

/// Unit normal of the triangle (a, b, c) (right-hand rule); zero for a degenerate triangle.
pub fn triangle_normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let n = cross(sub(b, a), sub(c, a));
    let l = norm(n);
    if l > 0.0 { scale(n, 1.0 / l) } else { [0.0; 3] }
}

/// Whether face `f` of a planar map (x, y) that should be counter-clockwise is flipped or
/// collapsed: its signed area is not positive (or not a number). The one flip predicate of the
/// plane; the sphere's is [`sphere::spherical_flipped`], the flat torus's
/// [`torus::FlatTorus::count_flipped`].
#[inline]
pub fn planar_flipped(map: &[[f64; 3]], f: [u32; 3]) -> bool {
    !(signed_area_2d(map[f[0] as usize], map[f[1] as usize], map[f[2] as usize]) > 0.0)
}

/// Number of faces of a planar map (x, y) whose signed area is not positive: the flipped or
/// collapsed faces of a map that should be counter-clockwise ([`planar_flipped`]).
pub fn count_nonpositive(map: &[[f64; 3]], faces: &[[u32; 3]]) -> usize {
    faces.iter().filter(|&&f| planar_flipped(map, f)).count()
}

/// Cotangents of the three corner angles of triangle (a, b, c): entry `k` is the cotangent of
/// the angle at corner `k`, `cot θ = (u·v)/|u×v|`. Degenerate corners give ±∞-free large values
/// bounded by the caller's use; a zero-area triangle returns zeros.
pub fn corner_cotangents(p: [[f64; 3]; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    let twice_area = norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    if twice_area <= 0.0 {
        return out;
    }
    for k in 0..3 {
        let u = sub(p[(k + 1) % 3], p[k]);
        let v = sub(p[(k + 2) % 3], p[k]);
        out[k] = dot(u, v) / twice_area;
    }
    out
}

/// Coordinates of the triangle's corners in its own orthonormal 2D frame: corner 0 at the
/// origin, corner 1 on the positive x axis, corner 2 in the upper half plane (so the local
/// triangle is counter-clockwise with respect to its normal).
pub fn local_frame(p: [[f64; 3]; 3]) -> [[f64; 2]; 3] {
    let e1 = sub(p[1], p[0]);
    let e2 = sub(p[2], p[0]);
    let l1 = norm(e1);
    if l1 == 0.0 {
        return [[0.0; 2]; 3];
    }
    let x = scale(e1, 1.0 / l1);
    let n = cross(e1, e2);
    let ln = norm(n);
    let y = if ln > 0.0 {
        cross(scale(n, 1.0 / ln), x)
    } else {
        [0.0; 3]
    };
    [[0.0, 0.0], [l1, 0.0], [dot(e2, x), dot(e2, y)]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_and_orientation() {
        let a = [0.0, 0.0, 0.0];
        let b = [2.0, 0.0, 0.0];
        let c = [0.0, 3.0, 0.0];
        assert_eq!(triangle_area(a, b, c), 3.0);
        assert_eq!(signed_area_2d(a, b, c), 3.0);
        assert_eq!(signed_area_2d(a, c, b), -3.0);
        assert_eq!(triangle_normal(a, b, c), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn cotangents_of_right_isoceles_triangle() {
        let c = corner_cotangents([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert!(c[0].abs() < 1e-15); // right angle
        assert!((c[1] - 1.0).abs() < 1e-15 && (c[2] - 1.0).abs() < 1e-15); // 45 degrees
        // Equilateral: cot 60° = 1/√3.
        let e = corner_cotangents([
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 3f64.sqrt() / 2.0, 0.0],
        ]);
        for v in e {
            assert!((v - 1.0 / 3f64.sqrt()).abs() < 1e-14);
        }
    }

    #[test]
    fn local_frame_preserves_lengths_and_area() {
        let p = [[1.0, 2.0, 3.0], [2.0, 4.0, 3.5], [0.0, 3.0, 5.0]];
        let q = local_frame(p);
        let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        assert!((d(q[0], q[1]) - norm(sub(p[1], p[0]))).abs() < 1e-12);
        assert!((d(q[1], q[2]) - norm(sub(p[2], p[1]))).abs() < 1e-12);
        assert!((d(q[2], q[0]) - norm(sub(p[0], p[2]))).abs() < 1e-12);
        let a2 = 0.5
            * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]));
        assert!((a2 - triangle_area(p[0], p[1], p[2])).abs() < 1e-12);
    }
}
