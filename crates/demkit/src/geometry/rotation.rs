//! The optimal rotation aligning point sets (Kabsch's problem), in closed form by Horn's
//! quaternion method: the rotation minimising Σ |R p_i − q_i|² is given by the unit quaternion
//! of the largest eigenvalue of a symmetric 4×4 matrix built from Σ p_i q_iᵀ.

use super::sphere::Mat3;

/// The rotation `R` minimising `Σ_i |R p_i − q_i|²` (identity for fewer than one pair).
pub fn optimal_rotation(p: &[[f64; 3]], q: &[[f64; 3]]) -> Mat3 {
    let mut s = [[0.0; 3]; 3];
    for (a, b) in p.iter().zip(q) {
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += a[i] * b[j];
            }
        }
    }
    let [[sxx, sxy, sxz], [syx, syy, syz], [szx, szy, szz]] = s;
    let n = [
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ];
    let (values, vectors) = jacobi_eigen4(n);
    let k = (0..4)
        .max_by(|&a, &b| values[a].total_cmp(&values[b]))
        .unwrap_or(0);
    let (w, x, y, z) = (vectors[0][k], vectors[1][k], vectors[2][k], vectors[3][k]);
    let l = (w * w + x * x + y * y + z * z).sqrt();
    if !(l > 0.0) {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    }
    let (w, x, y, z) = (w / l, x / l, y / l, z / l);
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 4×4 matrix by cyclic Jacobi rotations.
fn jacobi_eigen4(mut a: [[f64; 4]; 4]) -> ([f64; 4], [[f64; 4]; 4]) {
    let mut v = [[0.0; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..50 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let scale: f64 = (0..4).map(|i| a[i][i] * a[i][i]).sum::<f64>() + off;
        if off <= 1e-30 * scale.max(1e-300) {
            break;
        }
        for p in 0..3 {
            for q in p + 1..4 {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (row_p, row_q) = (a[p], a[q]);
                for k in 0..4 {
                    a[p][k] = c * row_p[k] - s * row_q[k];
                    a[q][k] = s * row_p[k] + c * row_q[k];
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2], a[3][3]], v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::mat_vec;

    fn rot(axis: [f64; 3], angle: f64) -> Mat3 {
        let l = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let [x, y, z] = axis.map(|a| a / l);
        let (s, c) = angle.sin_cos();
        let t = 1.0 - c;
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    }

    #[test]
    fn recovers_a_known_rotation() {
        let p: Vec<[f64; 3]> = (0..7)
            .map(|i| {
                let t = i as f64;
                [t.sin(), (1.3 * t).cos(), 0.2 * t - 0.5]
            })
            .collect();
        for (axis, angle) in [
            ([0.3, -1.0, 0.5], 2.5),
            ([0.0, 0.0, 1.0], 0.1),
            ([1.0, 1.0, 0.0], 3.1),
        ] {
            let r = rot(axis, angle);
            let q: Vec<[f64; 3]> = p.iter().map(|&x| mat_vec(&r, x)).collect();
            let found = optimal_rotation(&p, &q);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((found[i][j] - r[i][j]).abs() < 1e-10, "{found:?} vs {r:?}");
                }
            }
        }
    }

    #[test]
    fn noisy_targets_give_a_proper_rotation() {
        let p = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let q = [[0.9, 0.1, 0.0], [-0.1, 1.0, 0.05], [0.0, 0.0, 1.1]];
        let r = optimal_rotation(&p, &q);
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
            - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        assert!((det - 1.0).abs() < 1e-12);
    }
}
