//! Möbius area correction of a spherical conformal map (SDEM paper §3.1.1, after Choi et al.):
//! among the Möbius transformations of the sphere (equivalently, of the stereographic plane),
//! find the one minimising the mean |log area ratio| of the map, and compose with it. The
//! result is still conformal.
//!
//! Every Möbius transformation of the sphere is a rotation composed with
//! `φ_a(x) = (1 − |a|²)(x − a) / (1 − 2 a·x + |a|²) − a` for a point `a` of the open unit ball
//! (the ball automorphism sending `a` to the centre, restricted to the sphere). Rotations leave
//! areas unchanged, so the search runs over `a ∈ R³`, |a| < 1, with BFGS; the gradient is exact:
//! the chain rule through the triangle areas and the Jacobian of `φ_a` in `a`.

use crate::geometry::sphere::normalize;
use crate::geometry::{cross, dot, norm, scale, sub, triangle_area};
use rayon::prelude::*;

/// BFGS stops when an iteration lowers the objective by less than this fraction: the map
/// starts a density equalization that moves every face anyway (at a bound of 1e-10,
/// twistedball took 15 iterations and maxplanck 21; at this one 9 and 8, and the objective
/// differs by less than 5e-7).
const MIN_GAIN: f64 = 1e-6;

/// `φ_a(x)` (module docs): a Möbius transformation of the unit sphere sending `a/|a|`'s
/// neighbourhood outwards when |a| grows; `φ_0` is the identity.
pub fn mobius(a: [f64; 3], x: [f64; 3]) -> [f64; 3] {
    let aa = dot(a, a);
    let k = (1.0 - aa) / (1.0 - 2.0 * dot(a, x) + aa);
    sub(scale(sub(x, a), k), a)
}

/// `φ_a(x)` and its Jacobian in `a` (column `k` = ∂φ_a(x)/∂a_k). With `D = 1 − 2a·x + |a|²`
/// and `k = (1 − |a|²)/D`, `φ = k(x − a) − a`, so `∂φ/∂a_j = (x − a) ∂k/∂a_j − (k + 1) e_j`
/// with `∂k/∂a_j = 2((1 − |a|²)(x_j − a_j) − a_j D)/D²`.
fn mobius_and_jacobian(a: [f64; 3], x: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let aa = dot(a, a);
    let d = 1.0 - 2.0 * dot(a, x) + aa;
    let k = (1.0 - aa) / d;
    let xa = sub(x, a);
    let jac = std::array::from_fn(|j| {
        let dk = 2.0 * ((1.0 - aa) * xa[j] - a[j] * d) / (d * d);
        let mut col = scale(xa, dk);
        col[j] -= k + 1.0;
        col
    });
    (sub(scale(xa, k), a), jac)
}

/// Faces per block of the objective's sum (summed in face order within a block, blocks in
/// order: the same value whatever the threads).
const BLOCK: usize = 4096;

/// The areas of the faces of `y`, their total, the mean |log ratio| of the normalised areas to
/// the normalised targets (`log_target` = log of the normalised target weights), and, when
/// `signs` is asked for, the sign of every face's log ratio (the objective's derivative in it).
fn areas_and_objective(
    y: &[[f64; 3]],
    faces: &[[u32; 3]],
    log_target: &[f64],
    signs: Option<&mut Vec<f64>>,
) -> (Vec<f64>, f64, f64) {
    let areas: Vec<f64> = faces
        .par_iter()
        .map(|f| triangle_area(y[f[0] as usize], y[f[1] as usize], y[f[2] as usize]))
        .collect();
    let sum = areas.iter().sum::<f64>();
    let log_sum = sum.ln();
    let d: Vec<f64> = areas
        .par_iter()
        .zip(log_target.par_iter())
        .map(|(a, t)| a.ln() - log_sum - t)
        .collect();
    let s: f64 = d
        .par_chunks(BLOCK)
        .map(|c| c.iter().map(|x| x.abs()).sum::<f64>())
        .collect::<Vec<f64>>()
        .iter()
        .sum();
    if let Some(signs) = signs {
        *signs = d
            .iter()
            .map(|&x| {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            })
            .collect();
    }
    let j = s / faces.len() as f64;
    (areas, sum, if j.is_nan() { f64::INFINITY } else { j })
}

/// The mean |log ratio| of normalised map areas to normalised target areas.
fn objective(y: &[[f64; 3]], faces: &[[u32; 3]], log_target: &[f64]) -> f64 {
    areas_and_objective(y, faces, log_target, None).2
}

/// Objective and its gradient in `a`: the chain rule through the triangle areas and the
/// Jacobians of [`mobius_and_jacobian`].
fn objective_and_gradient(
    x: &[[f64; 3]],
    faces: &[[u32; 3]],
    log_target: &[f64],
    a: [f64; 3],
) -> (f64, [f64; 3]) {
    let (y, jac): (Vec<[f64; 3]>, Vec<[[f64; 3]; 3]>) =
        x.par_iter().map(|&p| mobius_and_jacobian(a, p)).unzip();
    let mut signs = Vec::new();
    let (areas, sum_a, j) = areas_and_objective(&y, faces, log_target, Some(&mut signs));
    let s_total: f64 = signs.iter().sum();
    let nf = faces.len() as f64;
    let grad = faces
        .par_iter()
        .enumerate()
        .map(|(t, f)| {
            let area = areas[t];
            if !(area > 0.0) {
                return [0.0; 3];
            }
            let dj_da = (signs[t] / area - s_total / sum_a) / nf;
            let p = f.map(|v| y[v as usize]);
            let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let nh = scale(n, 1.0 / norm(n));
            let mut g = [0.0; 3];
            for i in 0..3 {
                // ∂Area/∂p_i = ½ n̂ × (p_{i+2} − p_{i+1}).
                let da = scale(cross(nh, sub(p[(i + 2) % 3], p[(i + 1) % 3])), 0.5 * dj_da);
                let jv = &jac[f[i] as usize];
                for (k, gk) in g.iter_mut().enumerate() {
                    *gk += dot(da, jv[k]);
                }
            }
            g
        })
        .collect::<Vec<[f64; 3]>>()
        .iter()
        .fold([0.0; 3], |u, v| [u[0] + v[0], u[1] + v[1], u[2] + v[2]]);
    (j, grad)
}

/// The result of [`mobius_area_correction`].
#[derive(Debug, Clone)]
pub struct MobiusCorrection {
    /// The corrected map (unit vectors).
    pub map: Vec<[f64; 3]>,
    /// The parameter `a` of the optimal `φ_a`.
    pub a: [f64; 3],
    /// Mean |log area ratio| before and after.
    pub before: f64,
    /// See `before`.
    pub after: f64,
    /// BFGS iterations.
    pub iterations: usize,
}

/// Composes the spherical map `map` with the Möbius transformation minimising the mean of
/// |log((A(T)/ΣA) / (w(T)/Σw))|, where `A` are the mapped face areas and `w` the target
/// weights (the input's face areas for an area correction, or a population).
pub fn mobius_area_correction(
    map: &[[f64; 3]],
    faces: &[[u32; 3]],
    target: &[f64],
) -> MobiusCorrection {
    let sum_t: f64 = target.iter().sum();
    let log_target: Vec<f64> = target.iter().map(|t| (t / sum_t).ln()).collect();
    let eval = |a: [f64; 3]| objective_and_gradient(map, faces, &log_target, a);
    let value = |a: [f64; 3]| {
        let y: Vec<[f64; 3]> = map.par_iter().map(|&p| mobius(a, p)).collect();
        objective(&y, faces, &log_target)
    };
    let mut a = [0.0; 3];
    let (mut f, mut g) = eval(a);
    let before = f;
    let mut h = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut iterations = 0;
    for it in 0..100 {
        iterations = it;
        let mut p = [0.0; 3];
        for i in 0..3 {
            p[i] = -dot(h[i], g);
        }
        if !(dot(p, g) < 0.0) {
            h = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            p = scale(g, -1.0);
        }
        if norm(g) < 1e-12 {
            break;
        }
        // Backtracking (Armijo) line search inside the ball.
        let mut t = 1.0;
        let mut accepted = None;
        while t > 1e-12 {
            let cand = [a[0] + t * p[0], a[1] + t * p[1], a[2] + t * p[2]];
            if norm(cand) < 0.999 {
                let fc = value(cand);
                if fc <= f + 1e-4 * t * dot(g, p) {
                    accepted = Some(cand);
                    break;
                }
            }
            t *= 0.5;
        }
        let Some(a_new) = accepted else { break };
        let (f_new, g_new) = eval(a_new);
        let s = sub(a_new, a);
        let y = sub(g_new, g);
        let sy = dot(s, y);
        if sy > 1e-18 {
            // BFGS update of the inverse Hessian.
            let hy: [f64; 3] = std::array::from_fn(|i| dot(h[i], y));
            let yhy = dot(y, hy);
            let mut h2 = h;
            for (i, row) in h2.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x +=
                        ((sy + yhy) * s[i] * s[j]) / (sy * sy) - (hy[i] * s[j] + s[i] * hy[j]) / sy;
                }
            }
            h = h2;
        }
        let improvement = f - f_new;
        a = a_new;
        f = f_new;
        g = g_new;
        if improvement < MIN_GAIN * f.max(1e-12) {
            break;
        }
    }
    let corrected: Vec<[f64; 3]> = map.par_iter().map(|&p| normalize(mobius(a, p))).collect();
    let after = objective(&corrected, faces, &log_target);
    if !(after <= before) {
        return MobiusCorrection {
            map: map.to_vec(),
            a: [0.0; 3],
            before,
            after: before,
            iterations,
        };
    }
    MobiusCorrection {
        map: corrected,
        a,
        before,
        after,
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;

    #[test]
    fn mobius_maps_the_sphere_to_itself_and_the_identity_at_zero() {
        let a = [0.3, -0.2, 0.5];
        for i in 0..20 {
            let t = i as f64;
            let x = normalize([t.sin(), (2.0 * t).cos(), 0.3 * t - 2.0]);
            assert!((norm(mobius(a, x)) - 1.0).abs() < 1e-13);
            assert_eq!(mobius([0.0; 3], x), x);
        }
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let a = [0.3, -0.2, 0.25];
        let x = normalize([0.4, 0.7, -0.2]);
        let (y, jac) = mobius_and_jacobian(a, x);
        assert_eq!(y, mobius(a, x));
        let h = 1e-6;
        for k in 0..3 {
            let (mut ap, mut am) = (a, a);
            ap[k] += h;
            am[k] -= h;
            let fd = sub(mobius(ap, x), mobius(am, x)).map(|d| d / (2.0 * h));
            for i in 0..3 {
                assert!(
                    (fd[i] - jac[k][i]).abs() < 1e-8,
                    "∂φ_{i}/∂a_{k}: {} vs {}",
                    fd[i],
                    jac[k][i]
                );
            }
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let mesh = icosphere(2).unwrap();
        let x: Vec<[f64; 3]> = mesh
            .positions
            .iter()
            .map(|&p| mobius([0.2, 0.1, -0.3], p))
            .collect();
        let target = face_areas(&mesh.positions, &mesh.faces);
        let s: f64 = target.iter().sum();
        let lt: Vec<f64> = target.iter().map(|t| (t / s).ln()).collect();
        let a = [0.05, -0.1, 0.12];
        let (_, g) = objective_and_gradient(&x, &mesh.faces, &lt, a);
        let h = 1e-6;
        for k in 0..3 {
            let mut ap = a;
            ap[k] += h;
            let mut am = a;
            am[k] -= h;
            let fp = objective_and_gradient(&x, &mesh.faces, &lt, ap).0;
            let fm = objective_and_gradient(&x, &mesh.faces, &lt, am).0;
            let fd = (fp - fm) / (2.0 * h);
            assert!(
                (fd - g[k]).abs() < 1e-5 * (1.0 + g[k].abs()),
                "k={k}: {fd} vs {}",
                g[k]
            );
        }
    }

    #[test]
    fn uniform_map_stays_put_and_a_distorted_one_is_undone() {
        let mesh = icosphere(3).unwrap();
        let area = face_areas(&mesh.positions, &mesh.faces);
        // Already area-uniform (the icosphere against its own areas): the optimum is a = 0.
        let c = mobius_area_correction(&mesh.positions, &mesh.faces, &area);
        assert!(norm(c.a) < 1e-3, "a = {:?}", c.a);
        assert!(c.after <= c.before);
        // Distorted by a known Möbius map: the correction recovers an area-uniform map.
        let warped: Vec<[f64; 3]> = mesh
            .positions
            .iter()
            .map(|&p| mobius([0.0, 0.4, 0.3], p))
            .collect();
        let c = mobius_area_correction(&warped, &mesh.faces, &area);
        assert!(c.before > 0.3, "before {}", c.before);
        assert!(c.after < 0.02, "after {}", c.after);
    }
}
