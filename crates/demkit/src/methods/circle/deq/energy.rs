//! The DEQ energy of one face, with its gradient and a positive semi-definite Hessian.
//!
//! The paper's energy (4.2) weighs the density's variation against the Beltrami coefficient,
//! `∫|∇ρ|² + α ∫|μ|² + β ∫|∇μ|²`. demkit minimises its per-face form
//!
//! `E(f) = mean_T [ D(ρ̃_T) + α φ(|μ_T|) + η |μ_T|⁴ / (1 − |μ_T|²) ]`,
//!
//! with `ρ̃_T = Â_T / A_T` the face's relative density (`A_T` its area in the map, `Â_T` its
//! share of the area), `D(ρ̃) = (ρ̃ − 1)²` — what Var(ρ̃) measures, and a barrier against
//! collapse — or `(log ρ̃)²`, which Newton's method handles better far from equal densities,
//! `μ_T` the Beltrami coefficient of the map from the surface and `φ(m) = √(m² + ε²) − ε`, a
//! smoothed |μ|: the mean |μ| the report measures (with |μ|² the distortion would be spread
//! evenly instead of staying where the density needs it). Both |μ| and |μ|² stay bounded as a
//! triangle degenerates into a needle, so on their own they let the density buy area with
//! shape without limit (lion_5: 1 % of the faces stretched more than 87 : 1, and a remesh
//! through the map with area CV 1.2); the energy therefore adds, whatever α, the shape barrier
//! `η |μ|⁴ / (1 − |μ|²)` ([`BARRIER`]): negligible for a mild shear (10⁻³ at |μ| = 0.4), it
//! grows without bound as `|μ| → 1` (η = 0.05: lion_5 then 99 % of faces within 28 : 1 and a remesh with area CV 0.29, at Var(ρ̃) 0.0088 instead of 0.0054).
//!
//! With the source triangle's corners `q_k` in its own frame, `d_k = q_{k+2} − q_{k+1}` and
//! the image corners `w_k`, the map's complex derivatives are linear in the image:
//! `f_z = −i Σ d̄_k w_k / 4A`, `f_z̄ = i Σ d_k w_k / 4A`. The energy depends on `p = |f_z|²` and
//! `q = |f_z̄|²` alone (`det = p − q`, `|μ|² = q/p`), so its Hessian in `(f_z, f_z̄)` splits
//! into two turning directions, with eigenvalues `2 g_p` and `2 g_q`, and a 2×2 block on the
//! radial directions `f_z/|f_z|`, `f_z̄/|f_z̄|`; the projection onto positive semi-definite
//! matrices clips those four eigenvalues (an analytic eigensystem, as for isotropic
//! distortion energies).

use crate::geometry::local_frame;
use num_complex::Complex64 as C64;

/// The smoothing ε of |μ| in φ.
const EPSILON: f64 = 0.05;

/// The weight η of the shape barrier `η |μ|⁴ / (1 − |μ|²)`.
pub(crate) const BARRIER: f64 = 0.05;

/// The density misfit `D`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Misfit {
    /// `(ρ̃ − 1)²`.
    Square,
    /// `(log ρ̃)²`.
    Log,
}

/// One face's fixed data.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Face {
    /// `f_z = Σ a_k w_k`, `f_z̄ = Σ b_k w_k`.
    a: [C64; 3],
    b: [C64; 3],
    /// The source triangle's area.
    pub source_area: f64,
}

impl Face {
    /// The face with corners `p` on the surface.
    pub fn new(p: [[f64; 3]; 3]) -> Self {
        let q = local_frame(p).map(|c| C64::new(c[0], c[1]));
        let d: [C64; 3] = std::array::from_fn(|k| q[(k + 2) % 3] - q[(k + 1) % 3]);
        let area = 0.5 * (d[2].conj() * d[1]).im.abs();
        let i = C64::new(0.0, 1.0);
        Self {
            a: d.map(|dk| -i * dk.conj() / (4.0 * area)),
            b: d.map(|dk| i * dk / (4.0 * area)),
            source_area: area,
        }
    }

    /// `(f_z, f_z̄)` of the map sending the face to the image corners `w`.
    pub fn derivatives(&self, w: [[f64; 2]; 3]) -> (C64, C64) {
        let w = w.map(|c| C64::new(c[0], c[1]));
        (
            (0..3).map(|k| self.a[k] * w[k]).sum(),
            (0..3).map(|k| self.b[k] * w[k]).sum(),
        )
    }
}

/// `g(p, q)` and its first and second derivatives `(g, g_p, g_q, g_pp, g_pq, g_qq)`, for the
/// relative area target `k = Â/A_src` (so `ρ̃ = k / det`).
fn g(p: f64, q: f64, k: f64, alpha: f64, misfit: Misfit) -> Option<[f64; 6]> {
    let det = p - q;
    if !(det > 0.0) || !(p > 0.0) {
        return None;
    }
    let rho = k / det;
    // The density part as a function of det.
    let (d0, d1, d2) = match misfit {
        Misfit::Square => (
            (rho - 1.0).powi(2),
            -2.0 * rho * (rho - 1.0) / det,
            2.0 * rho * (3.0 * rho - 2.0) / (det * det),
        ),
        Misfit::Log => {
            let l = -rho.ln();
            (l * l, 2.0 * l / det, (2.0 - 2.0 * l) / (det * det))
        }
    };
    // The distortion part α(√(r + ε²) − ε) + η r²/(1 − r) with r = q/p = |μ|² < 1.
    let r = q / p;
    let s = (r + EPSILON * EPSILON).sqrt();
    let t = 1.0 - r;
    let barrier = BARRIER * r * r / t;
    let (h1, h2) = (
        alpha / (2.0 * s) + BARRIER * (1.0 / (t * t) - 1.0),
        -alpha / (4.0 * s * s * s) + BARRIER * 2.0 / (t * t * t),
    );
    let (r_p, r_q) = (-q / (p * p), 1.0 / p);
    let (r_pp, r_pq) = (2.0 * q / (p * p * p), -1.0 / (p * p));
    Some([
        d0 + alpha * (s - EPSILON) + barrier,
        d1 + h1 * r_p,
        -d1 + h1 * r_q,
        d2 + h2 * r_p * r_p + h1 * r_pp,
        -d2 + h2 * r_p * r_q + h1 * r_pq,
        d2 + h2 * r_q * r_q,
    ])
}

/// The face's energy for the image corners `w`; `None` when the image is folded or flat.
pub(crate) fn value(
    face: &Face,
    w: [[f64; 2]; 3],
    k: f64,
    alpha: f64,
    misfit: Misfit,
) -> Option<f64> {
    let (fz, fzb) = face.derivatives(w);
    g(fz.norm_sqr(), fzb.norm_sqr(), k, alpha, misfit).map(|v| v[0])
}

/// The face's energy, its gradient in the image coordinates `(x₀, y₀, x₁, y₁, x₂, y₂)` and a
/// positive semi-definite approximation of its Hessian there ([`lift`]); `None` for a folded
/// image.
pub(crate) fn derivatives(
    face: &Face,
    w: [[f64; 2]; 3],
    k: f64,
    alpha: f64,
    misfit: Misfit,
) -> Option<(f64, [f64; 6], [[f64; 6]; 6])> {
    let (fz, fzb) = face.derivatives(w);
    let d = g(fz.norm_sqr(), fzb.norm_sqr(), k, alpha, misfit)?;
    Some(lift(face, fz, fzb, d))
}

/// A face energy `E(p, q)` of `p = |f_z|²`, `q = |f_z̄|²`, given by its value and derivatives
/// `[E, E_p, E_q, E_pp, E_pq, E_qq]` at the face's `(f_z, f_z̄)`, carried to the image
/// coordinates: the value, the gradient and the Hessian with each of its four eigenvalues
/// (two turning directions, a 2 × 2 radial block) replaced by its absolute value
/// (docs/deviations.md, DEQ: why not clipped at 0).
pub(crate) fn lift(face: &Face, fz: C64, fzb: C64, d: [f64; 6]) -> (f64, [f64; 6], [[f64; 6]; 6]) {
    let [e, gp, gq, gpp, gpq, gqq] = d;
    let (p, q) = (fz.norm_sqr(), fzb.norm_sqr());
    // Unit radial directions of f_z and f_z̄ (any one when one is 0).
    let unit = |z: C64, r: f64| {
        if r > 0.0 {
            z / r.sqrt()
        } else {
            C64::new(1.0, 0.0)
        }
    };
    let (ua, ub) = (unit(fz, p), unit(fzb, q));
    let i = C64::new(0.0, 1.0);
    // A direction δ of f_z (or f_z̄) maps to the image coordinates through the linear map
    // w ↦ f_z: the image gradient of Re(conj(δ) f_z) is (Re(conj(δ) a_k), Re(conj(δ) i a_k)).
    let along = |coef: &[C64; 3], dir: C64| -> [f64; 6] {
        let mut out = [0.0; 6];
        for kk in 0..3 {
            let c = dir.conj() * coef[kk];
            out[2 * kk] = c.re;
            out[2 * kk + 1] = (c * i).re;
        }
        out
    };
    let ra = along(&face.a, ua);
    let rb = along(&face.b, ub);
    let ta = along(&face.a, i * ua);
    let tb = along(&face.b, i * ub);
    // Gradient: ∇p = 2√p · ra, ∇q = 2√q · rb.
    let (sp, sq) = (p.sqrt(), q.sqrt());
    let grad: [f64; 6] = std::array::from_fn(|j| 2.0 * gp * sp * ra[j] + 2.0 * gq * sq * rb[j]);
    // Hessian: the turning directions, then the radial 2×2 block.
    let mut hess = [[0.0; 6]; 6];
    let mut add = |lambda: f64, v: &[f64; 6]| {
        let lambda = lambda.abs();
        for r in 0..6 {
            for c in 0..6 {
                hess[r][c] += lambda * v[r] * v[c];
            }
        }
    };
    add(2.0 * gp, &ta);
    add(2.0 * gq, &tb);
    let m11 = 4.0 * p * gpp + 2.0 * gp;
    let m22 = 4.0 * q * gqq + 2.0 * gq;
    let m12 = 4.0 * sp * sq * gpq;
    let half_trace = 0.5 * (m11 + m22);
    let radius = (0.25 * (m11 - m22).powi(2) + m12 * m12).sqrt();
    for lambda in [half_trace + radius, half_trace - radius] {
        // Eigenvector of [[m11, m12], [m12, m22]] for lambda.
        let (c1, c2) = if m12.abs() > 1e-300 {
            (m12, lambda - m11)
        } else if (lambda - m11).abs() <= (lambda - m22).abs() {
            (1.0, 0.0)
        } else {
            (0.0, 1.0)
        };
        let norm = c1.hypot(c2);
        if norm > 0.0 {
            let v: [f64; 6] = std::array::from_fn(|j| (c1 * ra[j] + c2 * rb[j]) / norm);
            add(lambda, &v);
        }
    }
    (e, grad, hess)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face() -> Face {
        Face::new([[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.1, 0.9, -0.2]])
    }

    const W: [[f64; 2]; 3] = [[0.1, 0.0], [1.3, 0.4], [0.2, 1.1]];

    #[test]
    fn the_identity_is_conformal_and_area_preserving() {
        let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.5, 0.0]];
        let f = Face::new(p);
        let w = local_frame(p);
        // k = 1: the target area is the source area; the map is the identity in the frame.
        let e = value(&f, w, 1.0, 0.7, Misfit::Square).unwrap();
        assert!(e.abs() < 1e-12, "{e}");
        // A flat image has no energy.
        assert!(
            value(
                &f,
                [[0.0; 2], [1.0, 0.0], [2.0, 0.0]],
                1.0,
                0.7,
                Misfit::Square
            )
            .is_none()
        );
    }

    #[test]
    fn gradient_matches_finite_differences() {
        for misfit in [Misfit::Square, Misfit::Log] {
            let (_, g, _) = derivatives(&face(), W, 0.8, 0.7, misfit).unwrap();
            for j in 0..6 {
                let h = 1e-6;
                let mut a = W;
                a[j / 2][j % 2] += h;
                let mut b = W;
                b[j / 2][j % 2] -= h;
                let fd = (value(&face(), a, 0.8, 0.7, misfit).unwrap()
                    - value(&face(), b, 0.8, 0.7, misfit).unwrap())
                    / (2.0 * h);
                assert!(
                    (fd - g[j]).abs() < 1e-6 * (1.0 + g[j].abs()),
                    "{misfit:?} {j}: {fd} vs {}",
                    g[j]
                );
            }
        }
    }

    #[test]
    fn hessian_is_the_clipped_exact_one() {
        // Where the exact Hessian is positive definite the projection leaves it alone: compare
        // with finite differences of the gradient at a point near the minimum.
        let f = face();
        let base = local_frame([[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.1, 0.9, -0.2]]);
        let w = [
            base[0],
            [base[1][0] * 1.05, base[1][1]],
            [base[2][0], base[2][1] * 0.97],
        ];
        let (_, _, h) = derivatives(&f, w, 1.0, 0.0, Misfit::Log).unwrap();
        for j in 0..6 {
            let eps = 1e-6;
            let mut a = w;
            a[j / 2][j % 2] += eps;
            let mut b = w;
            b[j / 2][j % 2] -= eps;
            let ga = derivatives(&f, a, 1.0, 0.0, Misfit::Log).unwrap().1;
            let gb = derivatives(&f, b, 1.0, 0.0, Misfit::Log).unwrap().1;
            for i in 0..6 {
                let fd = (ga[i] - gb[i]) / (2.0 * eps);
                // The log misfit alone is not convex everywhere; the projected Hessian is the
                // exact one plus a positive semi-definite correction, so compare the diagonal.
                if i == j {
                    assert!(h[i][i] + 1e-6 >= fd, "{i}: {} < {fd}", h[i][i]);
                }
            }
        }
        // Positive semi-definite: vᵀ H v ≥ 0 for a few directions.
        let (_, _, h) = derivatives(&f, W, 0.3, 0.7, Misfit::Square).unwrap();
        for s in 0..20 {
            let v: [f64; 6] = std::array::from_fn(|j| ((s * 7 + j * 13) % 11) as f64 - 5.0);
            let q: f64 = (0..6)
                .map(|r| (0..6).map(|c| v[r] * h[r][c] * v[c]).sum::<f64>())
                .sum();
            assert!(q >= -1e-9, "{q}");
        }
    }
}
