//! Beltrami coefficient μ = f_z̄ / f_z of a piecewise-affine map (DEQ paper (3.1), (B.2)).

use crate::geometry::local_frame;
use num_complex::Complex64;
use rayon::prelude::*;

/// Beltrami coefficient of the affine map sending the planar triangle `s` to the planar
/// triangle `t` (corners in the same order): with the map's partial derivatives
/// `a = u_x, b = u_y, c = v_x, d = v_y`, `μ = ((a − d) + i(c + b)) / ((a + d) + i(c − b))` (B.2).
/// A degenerate source gives 0; a map collapsing the triangle gives |μ| = 1; an
/// orientation-reversing map gives |μ| > 1.
pub fn triangle_beltrami(s: [[f64; 2]; 3], t: [[f64; 2]; 3]) -> Complex64 {
    let (x1, y1) = (s[1][0] - s[0][0], s[1][1] - s[0][1]);
    let (x2, y2) = (s[2][0] - s[0][0], s[2][1] - s[0][1]);
    let det = x1 * y2 - x2 * y1;
    if det == 0.0 {
        return Complex64::new(0.0, 0.0);
    }
    let (u1, u2) = (t[1][0] - t[0][0], t[2][0] - t[0][0]);
    let (v1, v2) = (t[1][1] - t[0][1], t[2][1] - t[0][1]);
    // [x1 y1; x2 y2] [u_x; u_y] = [u1; u2]
    let a = (u1 * y2 - u2 * y1) / det;
    let b = (x1 * u2 - x2 * u1) / det;
    let c = (v1 * y2 - v2 * y1) / det;
    let d = (x1 * v2 - x2 * v1) / det;
    let fz = Complex64::new(a + d, c - b);
    let fzbar = Complex64::new(a - d, c + b);
    if fz.norm_sqr() == 0.0 {
        // f_z = 0: orientation-reversing (anti-conformal) or constant map.
        return if fzbar.norm_sqr() == 0.0 {
            Complex64::new(1.0, 0.0)
        } else {
            Complex64::new(f64::INFINITY, 0.0)
        };
    }
    fzbar / fz
}

/// The triangle's x, y coordinates (the plane z = 0).
fn planar(p: [[f64; 3]; 3]) -> [[f64; 2]; 3] {
    p.map(|q| [q[0], q[1]])
}

/// Beltrami coefficient per face of the map from `source` to `target` (same connectivity),
/// each face's corners brought to the plane by `source_2d` and `target_2d`.
fn per_face<S, T>(
    source: &[[f64; 3]],
    target: &[[f64; 3]],
    faces: &[[u32; 3]],
    source_2d: S,
    target_2d: T,
) -> Vec<Complex64>
where
    S: Fn([[f64; 3]; 3]) -> [[f64; 2]; 3] + Sync,
    T: Fn([[f64; 3]; 3]) -> [[f64; 2]; 3] + Sync,
{
    faces
        .par_iter()
        .map(|f| {
            let s = source_2d(f.map(|v| source[v as usize]));
            let t = target_2d(f.map(|v| target[v as usize]));
            triangle_beltrami(s, t)
        })
        .collect()
}

/// Beltrami coefficient per face of the map from the planar mesh `source` (x, y) to the planar
/// mesh `target` (x, y), same connectivity.
pub fn beltrami_coefficient(
    source: &[[f64; 3]],
    target: &[[f64; 3]],
    faces: &[[u32; 3]],
) -> Vec<Complex64> {
    per_face(source, target, faces, planar, planar)
}

/// Beltrami coefficient per face of the map from a surface in R³ (each triangle in its own
/// orthonormal frame, [`local_frame`]) to the planar mesh `target` (x, y).
pub fn beltrami_coefficient_surface(
    surface: &[[f64; 3]],
    target: &[[f64; 3]],
    faces: &[[u32; 3]],
) -> Vec<Complex64> {
    per_face(surface, target, faces, local_frame, planar)
}

/// Beltrami coefficient per face of the map from the planar mesh `plane` (x, y) to a surface
/// in R³ with the same connectivity (each triangle in its own orthonormal frame,
/// [`local_frame`]), e.g. of a stereographic map onto an ellipsoid.
pub fn beltrami_coefficient_plane_to_surface(
    plane: &[[f64; 3]],
    surface: &[[f64; 3]],
    faces: &[[u32; 3]],
) -> Vec<Complex64> {
    per_face(plane, surface, faces, planar, local_frame)
}

/// Beltrami coefficient per face of the map between two surfaces in R³ with the same
/// connectivity (e.g. the input surface and its spherical image), each triangle in its own
/// orthonormal frame ([`local_frame`], counter-clockwise with respect to the face order).
pub fn beltrami_coefficient_surfaces(
    source: &[[f64; 3]],
    target: &[[f64; 3]],
    faces: &[[u32; 3]],
) -> Vec<Complex64> {
    per_face(source, target, faces, local_frame, local_frame)
}

/// [`beltrami_coefficient_surfaces`] with the source's triangles already in their frames
/// (`source_frames[i]`: face i by [`local_frame`]), for many maps of one surface.
pub fn beltrami_coefficient_from_frames(
    source_frames: &[[[f64; 2]; 3]],
    target: &[[f64; 3]],
    faces: &[[u32; 3]],
) -> Vec<Complex64> {
    faces
        .par_iter()
        .zip(source_frames.par_iter())
        .map(|(f, &s)| triangle_beltrami(s, local_frame(f.map(|v| target[v as usize]))))
        .collect()
}

/// Truncation 𝕀 of the SDEM paper (3.19): `μ` if `|μ| < 1`, else `(1 − δ) μ / |μ|`
/// (non-finite μ becomes `1 − δ`).
pub fn truncate(mu: Complex64, delta: f64) -> Complex64 {
    let r = mu.norm();
    if r < 1.0 {
        mu
    } else if r.is_finite() {
        mu * ((1.0 - delta) / r)
    } else {
        Complex64::new(1.0 - delta, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.2, 0.9]];

    fn apply(s: [[f64; 2]; 3], f: impl Fn(Complex64) -> Complex64) -> [[f64; 2]; 3] {
        s.map(|p| {
            let w = f(Complex64::new(p[0], p[1]));
            [w.re, w.im]
        })
    }

    #[test]
    fn cached_source_frames_give_the_same_coefficients() {
        let mesh = crate::generate::icosphere(2).unwrap();
        let target: Vec<[f64; 3]> = mesh
            .positions
            .iter()
            .map(|p| [p[0], 2.0 * p[1], 0.5 * p[2] + 0.1 * p[0] * p[0]])
            .collect();
        let frames: Vec<[[f64; 2]; 3]> = mesh
            .faces
            .iter()
            .map(|f| local_frame(f.map(|v| mesh.positions[v as usize])))
            .collect();
        let a = beltrami_coefficient_surfaces(&mesh.positions, &target, &mesh.faces);
        let b = beltrami_coefficient_from_frames(&frames, &target, &mesh.faces);
        assert!(a.iter().any(|m| m.norm() > 0.1));
        assert_eq!(a, b);
    }

    #[test]
    fn conformal_affine_map_has_zero_mu() {
        let a = Complex64::new(1.3, -0.7);
        let t = apply(S, |z| a * z + Complex64::new(2.0, 1.0));
        assert!(triangle_beltrami(S, t).norm() < 1e-14);
    }

    #[test]
    fn stretch_has_known_mu() {
        // f(z) = z + k z̄ has μ = k exactly.
        let k = Complex64::new(0.3, 0.2);
        let t = apply(S, |z| z + k * z.conj());
        assert!((triangle_beltrami(S, t) - k).norm() < 1e-14);
        // Composition with a conformal map afterwards leaves μ unchanged (2.8).
        let t2 = apply(t, |w| Complex64::new(0.0, 2.0) * w);
        assert!((triangle_beltrami(S, t2) - k).norm() < 1e-14);
    }

    #[test]
    fn reflection_has_modulus_above_one() {
        let t = apply(S, |z| z.conj() + 0.1 * z);
        assert!(triangle_beltrami(S, t).norm() > 1.0);
    }

    #[test]
    fn surface_version_is_invariant_to_rigid_motion() {
        let tri3 = [[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 0.2, 1.9]];
        // The triangle (0,0),(1,0),(0.2,0.9) placed in the plane x = 0.
        let target = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, 0.9, 0.0]];
        let mu = beltrami_coefficient_surface(&tri3, &target, &[[0, 1, 2]]);
        assert!(mu[0].norm() < 1e-14);
    }

    #[test]
    fn truncation() {
        let m = Complex64::new(0.0, 2.0);
        assert!((truncate(m, 0.1) - Complex64::new(0.0, 0.9)).norm() < 1e-15);
        let s = Complex64::new(0.5, 0.0);
        assert_eq!(truncate(s, 0.1), s);
    }
}
