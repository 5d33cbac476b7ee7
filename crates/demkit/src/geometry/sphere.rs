//! The unit sphere: stereographic projections, the spherical orientation test, rotations.
//!
//! Both projections are orientation-preserving from the sphere seen from outside to the plane
//! (a face whose corners are counter-clockwise around the outward normal is counter-clockwise
//! in the plane), so planar operators that expect counter-clockwise faces apply directly:
//! - [`project_from_north`]: the north pole goes to ∞, the south pole to 0;
//! - [`project_from_south`]: the south pole goes to ∞, the north pole to 0.

use super::vec3::{cross, dot, norm, scale};

/// Stereographic projection from the north pole (0, 0, 1): `(x − i y) / (1 − z)`, as (re, im, 0).
#[inline]
pub fn project_from_north(p: [f64; 3]) -> [f64; 3] {
    let d = 1.0 - p[2];
    [p[0] / d, -p[1] / d, 0.0]
}

/// Inverse of [`project_from_north`]: `w ↦ (2 Re w, −2 Im w, |w|² − 1) / (1 + |w|²)`.
#[inline]
pub fn unproject_from_north(w: [f64; 3]) -> [f64; 3] {
    let r2 = w[0] * w[0] + w[1] * w[1];
    let d = 1.0 + r2;
    [2.0 * w[0] / d, -2.0 * w[1] / d, (r2 - 1.0) / d]
}

/// Stereographic projection from the south pole (0, 0, −1): `(x + i y) / (1 + z)`.
#[inline]
pub fn project_from_south(p: [f64; 3]) -> [f64; 3] {
    let d = 1.0 + p[2];
    [p[0] / d, p[1] / d, 0.0]
}

/// Inverse of [`project_from_south`]: `w ↦ (2 Re w, 2 Im w, 1 − |w|²) / (1 + |w|²)`.
#[inline]
pub fn unproject_from_south(w: [f64; 3]) -> [f64; 3] {
    let r2 = w[0] * w[0] + w[1] * w[1];
    let d = 1.0 + r2;
    [2.0 * w[0] / d, 2.0 * w[1] / d, (1.0 - r2) / d]
}

/// `det(a, b, c) = ⅓ ((b − a) × (c − a)) · (a + b + c)`: positive when the face (a, b, c) of a
/// sphere around the origin is counter-clockwise seen from outside. Invariant under positive
/// scaling of each corner, so it is the same before and after projecting onto the sphere.
#[inline]
pub fn spherical_orientation(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    dot(a, cross(b, c))
}

/// Whether face `f` of a map onto the unit sphere is flipped: not counter-clockwise seen from
/// outside ([`spherical_orientation`] not positive, or not a number). The one flip predicate of
/// the sphere.
#[inline]
pub fn spherical_flipped(map: &[[f64; 3]], f: [u32; 3]) -> bool {
    !(spherical_orientation(map[f[0] as usize], map[f[1] as usize], map[f[2] as usize]) > 0.0)
}

/// `p / |p|` (the origin stays put).
#[inline]
pub fn normalize(p: [f64; 3]) -> [f64; 3] {
    let l = norm(p);
    if l > 0.0 { scale(p, 1.0 / l) } else { p }
}

/// A 3×3 matrix, rows first.
pub type Mat3 = [[f64; 3]; 3];

/// `m p`.
#[inline]
pub fn mat_vec(m: &Mat3, p: [f64; 3]) -> [f64; 3] {
    [dot(m[0], p), dot(m[1], p), dot(m[2], p)]
}

/// `mᵀ p`.
#[inline]
pub fn mat_t_vec(m: &Mat3, p: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * p[0] + m[1][0] * p[1] + m[2][0] * p[2],
        m[0][1] * p[0] + m[1][1] * p[1] + m[2][1] * p[2],
        m[0][2] * p[0] + m[1][2] * p[1] + m[2][2] * p[2],
    ]
}

/// A rotation sending the unit vector `c` to the north pole (0, 0, 1): its rows are an
/// orthonormal frame (u, v, c) with u × v = c.
pub fn rotation_to_north(c: [f64; 3]) -> Mat3 {
    let c = normalize(c);
    // Any vector not parallel to c.
    let t = if c[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = normalize(cross(t, c));
    let v = cross(c, u);
    [u, v, c]
}

/// `n` near-uniform unit vectors: the Fibonacci spiral `z_k = 1 − (2k + 1)/n`, longitude
/// `k · π(3 − √5)` (every point has the same share `4π/n` of the sphere's area).
pub fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - (2 * k + 1) as f64 / n as f64;
            let rho = (1.0 - z * z).max(0.0).sqrt();
            let (s, c) = (golden * k as f64).sin_cos();
            [rho * c, rho * s, z]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_points_are_unit_and_balanced() {
        let p = fibonacci_sphere(1000);
        let mut c = [0.0; 3];
        for q in &p {
            assert!(((q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt() - 1.0).abs() < 1e-12);
            for d in 0..3 {
                c[d] += q[d] / 1000.0;
            }
        }
        assert!(c.iter().all(|x| x.abs() < 1e-2), "{c:?}");
        // Upper hemisphere holds half the points.
        assert_eq!(p.iter().filter(|q| q[2] > 0.0).count(), 500);
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < tol)
    }

    #[test]
    fn projections_round_trip() {
        for i in 0..50 {
            let t = i as f64 * 0.37;
            let p = normalize([t.sin() * 2.0, (1.7 * t).cos(), (0.3 * t).sin() * 0.9]);
            if p[2] < 0.99 {
                assert!(close(unproject_from_north(project_from_north(p)), p, 1e-12));
            }
            if p[2] > -0.99 {
                assert!(close(unproject_from_south(project_from_south(p)), p, 1e-12));
            }
            let w = [t.cos() * 3.0, t.sin() * 0.5, 0.0];
            assert!(close(project_from_north(unproject_from_north(w)), w, 1e-11));
            assert!(close(project_from_south(unproject_from_south(w)), w, 1e-11));
        }
        // The poles.
        assert!(close(project_from_north([0.0, 0.0, -1.0]), [0.0; 3], 1e-15));
        assert!(close(project_from_south([0.0, 0.0, 1.0]), [0.0; 3], 1e-15));
    }

    #[test]
    fn projections_preserve_orientation() {
        // A small outward (counter-clockwise seen from outside) face near each point.
        for p in [
            normalize([0.3, -0.2, -0.9]),
            normalize([0.1, 0.5, 0.8]),
            normalize([1.0, 0.2, 0.1]),
        ] {
            let r = rotation_to_north(p);
            // Triangle around the north pole, rotated to p.
            let q = [[0.01, 0.0, 1.0], [0.0, 0.01, 1.0], [-0.01, -0.01, 1.0]]
                .map(|x| mat_t_vec(&r, normalize(x)));
            assert!(spherical_orientation(q[0], q[1], q[2]) > 0.0);
            for proj in [project_from_north, project_from_south] {
                let w = q.map(proj);
                assert!(crate::geometry::signed_area_2d(w[0], w[1], w[2]) > 0.0);
            }
        }
    }

    #[test]
    fn rotation_to_north_is_a_rotation() {
        let c = normalize([0.2, -0.7, 0.4]);
        let r = rotation_to_north(c);
        assert!(close(mat_vec(&r, c), [0.0, 0.0, 1.0], 1e-14));
        assert!((dot(r[0], cross(r[1], r[2])) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn orientation_test_matches_design_formula() {
        let (a, b, c) = ([1.0, 0.1, 0.0], [0.0, 1.0, 0.2], [0.1, 0.0, 1.0]);
        let f = dot(
            cross(super::super::sub(b, a), super::super::sub(c, a)),
            super::super::add(super::super::add(a, b), c),
        );
        assert!((f - 3.0 * spherical_orientation(a, b, c)).abs() < 1e-14);
    }
}
