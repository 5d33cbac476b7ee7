//! Cotangent Laplacian and lumped mass.

use crate::geometry::corner_cotangents;
use rayon::prelude::*;

/// Per-face edge weights of the cotangent Laplacian (B.6): entry `c` of face `f` is
/// `½ cot θ_c`, the contribution of face `f` to the edge opposite its corner `c`.
/// Assembled with [`crate::linalg::StiffnessPattern::assemble`] this gives the matrix `L` of
/// (4.34), positive semi-definite with `L_ij = −½ (cot α_ij + cot β_ij)`.
pub fn cotangent_weights(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut w = Vec::new();
    cotangent_weights_into(positions, faces, &mut w);
    w
}

/// As [`cotangent_weights`], reusing the output buffer (no allocation once it has grown).
pub fn cotangent_weights_into(positions: &[[f64; 3]], faces: &[[u32; 3]], out: &mut Vec<[f64; 3]>) {
    out.resize(faces.len(), [0.0; 3]);
    out.par_iter_mut().zip(faces.par_iter()).for_each(|(w, f)| {
        let c = corner_cotangents([
            positions[f[0] as usize],
            positions[f[1] as usize],
            positions[f[2] as usize],
        ]);
        *w = [0.5 * c[0], 0.5 * c[1], 0.5 * c[2]];
    });
}

/// Lumped mass (vertex area) (4.24): `A(i) = ⅓ Σ_{T ∋ i} Area(T)`, from precomputed face areas.
pub fn lumped_mass(n_vertices: usize, faces: &[[u32; 3]], face_areas: &[f64]) -> Vec<f64> {
    let mut m = vec![0.0; n_vertices];
    for (f, &a) in faces.iter().zip(face_areas) {
        for &v in f {
            m[v as usize] += a / 3.0;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;
    use crate::geometry::face_areas;
    use crate::linalg::StiffnessPattern;

    #[test]
    fn laplacian_of_linear_function_vanishes_inside() {
        // A jittered planar grid: the cotangent Laplacian reproduces linear functions exactly.
        let (pos, faces, boundary) = grid(6, 0.15);
        let p = StiffnessPattern::new(pos.len(), &faces, None);
        let w = cotangent_weights(&pos, &faces);
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[], &mut v);
        let x: Vec<f64> = pos.iter().map(|q| 2.0 * q[0] - 3.0 * q[1] + 1.0).collect();
        let y = p.mul(&v, &x);
        for (i, yi) in y.iter().enumerate() {
            if !boundary[i] {
                assert!(yi.abs() < 1e-12, "vertex {i}: {yi}");
            }
        }
        // Constants are in the kernel everywhere.
        let ones = vec![1.0; pos.len()];
        assert!(p.mul(&v, &ones).iter().all(|r| r.abs() < 1e-12));
    }

    #[test]
    fn dirichlet_energy_of_linear_function_is_area_times_gradient_squared() {
        let (pos, faces, _) = grid(5, 0.2);
        let p = StiffnessPattern::new(pos.len(), &faces, None);
        let w = cotangent_weights(&pos, &faces);
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&w, &[], &mut v);
        let x: Vec<f64> = pos.iter().map(|q| 3.0 * q[0] + 4.0 * q[1]).collect();
        let e: f64 = x.iter().zip(p.mul(&v, &x)).map(|(a, b)| a * b).sum();
        let area: f64 = face_areas(&pos, &faces).iter().sum();
        assert!((e - 25.0 * area).abs() < 1e-10 * e);
    }

    #[test]
    fn masses_sum_to_area() {
        let (pos, faces, _) = grid(4, 0.1);
        let a = face_areas(&pos, &faces);
        let m = lumped_mass(pos.len(), &faces, &a);
        let total: f64 = a.iter().sum();
        assert!((m.iter().sum::<f64>() - total).abs() < 1e-12);
    }
}
