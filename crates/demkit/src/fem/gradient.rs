//! Face gradient of a piecewise-linear vertex function (4.37).

use crate::geometry::{add, cross, norm, scale, sub};
use rayon::prelude::*;

/// Gradient of the piecewise-linear interpolant of `values` on every face (4.37):
/// `∇f(T) = (1 / 2A) N × (f_i e_jk + f_j e_ki + f_k e_ij)`, a vector in the face's plane.
/// Degenerate faces get a zero gradient.
pub fn face_gradient(positions: &[[f64; 3]], faces: &[[u32; 3]], values: &[f64]) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    face_gradient_into(positions, faces, values, &mut out);
    out
}

/// As [`face_gradient`], reusing the output buffer.
pub fn face_gradient_into(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    values: &[f64],
    out: &mut Vec<[f64; 3]>,
) {
    out.resize(faces.len(), [0.0; 3]);
    out.par_iter_mut().zip(faces.par_iter()).for_each(|(g, f)| {
        let [i, j, k] = f.map(|v| v as usize);
        let (pi, pj, pk) = (positions[i], positions[j], positions[k]);
        let n2 = cross(sub(pj, pi), sub(pk, pi)); // = 2A N
        let twice_area = norm(n2);
        if twice_area <= 0.0 {
            *g = [0.0; 3];
            return;
        }
        let s = add(
            add(scale(sub(pk, pj), values[i]), scale(sub(pi, pk), values[j])),
            scale(sub(pj, pi), values[k]),
        );
        // (1/2A) N × s with N = n2 / 2A.
        *g = scale(cross(n2, s), 1.0 / (twice_area * twice_area));
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_of_linear_function_is_exact() {
        // A tilted triangle in 3D; f(x) = g · x with g in the triangle's plane.
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 2.0, 0.5]];
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let g0 = [0.3, -1.2, 2.0];
        // Project g0 onto the plane.
        let nn = scale(n, 1.0 / norm(n));
        let g = sub(g0, scale(nn, crate::geometry::dot(g0, nn)));
        let values: Vec<f64> = p
            .iter()
            .map(|x| crate::geometry::dot(g, *x) + 5.0)
            .collect();
        let out = face_gradient(&p, &[[0, 1, 2]], &values);
        for d in 0..3 {
            assert!((out[0][d] - g[d]).abs() < 1e-12);
        }
    }

    #[test]
    fn constant_has_zero_gradient_and_degenerate_face_is_safe() {
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert_eq!(
            face_gradient(&p, &[[0, 1, 2]], &[1.0, 2.0, 3.0])[0],
            [0.0; 3]
        );
        let q = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let g = face_gradient(&q, &[[0, 1, 2]], &[4.0, 4.0, 4.0])[0];
        assert!(norm(g) < 1e-15);
    }
}
