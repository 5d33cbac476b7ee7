//! Which homology classes go to the two sides of the target rectangle.
//!
//! Let `U = (U₁, U₂)` be the harmonic map onto the unit lattice (generator `k` has period
//! `e_k`) and `G` the Gram matrix of its Dirichlet energy
//! ([`super::periodic_harmonic::dirichlet_gram`]). Every map onto the flat torus
//! `R² / (aZ × bZ)`, `a = 2πR`, `b = 2πr`, that is harmonic with a lattice isomorphism as
//! periods is `X = diag(a, b) P U` for an integer matrix `P` with `det P = ±1`: row `p₁` of `P`
//! is the cohomology class sent onto the `a` side, `p₂` the one sent onto the `b` side. Its
//! Dirichlet energy is `E(P) = a² p₁ᵀ G p₁ + b² p₂ᵀ G p₂`, and since its image area is always
//! `ab`, `E / 2ab ≥ 1` is its mean conformal distortion (1 only for a conformal map).
//!
//! The least energy is reached by a Lagrange–Gauss reduced basis of `Z²` in the norm
//! `|p|² = pᵀ G p`, the shortest class on the longer side: any basis `(p₁, p₂)` has both
//! `|p₁|, |p₂| ≥ λ₁` and one of them `≥ λ₂` (the successive minima), so
//! `E ≥ min(a²λ₂² + b²λ₁², a²λ₁² + b²λ₂²) = a²λ₁² + b²λ₂²` when `a ≥ b`, which the reduced
//! basis attains. Geometrically: `G⁻¹` is, up to scale, the Gram matrix of the conformal
//! period lattice, and the reduced basis is the pair of shortest conformal periods, the
//! longest cycle in the conformal structure (small `|p|` means a slowly varying, long-period
//! coordinate) going along the `2πR` side.

use crate::{Error, Result};

/// Reduction steps allowed (the Lagrange–Gauss reduction needs `O(log(cond G))`).
const MAX_STEPS: usize = 200;

/// The unimodular integer matrix `P` (rows `p₁`, `p₂`) minimising
/// `a² p₁ᵀ G p₁ + b² p₂ᵀ G p₂` for any `a ≥ b > 0`: a Lagrange–Gauss reduced basis of `Z²`
/// in the norm of the positive definite `g`, shortest vector first.
///
/// Errors: [`Error::Numerical`] when `g` is not finite and positive definite.
pub fn reduced_basis(g: [[f64; 2]; 2]) -> Result<[[i64; 2]; 2]> {
    let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    if !(g.iter().flatten().all(|x| x.is_finite()) && g[0][0] > 0.0 && det > 0.0) {
        return Err(Error::Numerical(format!(
            "the periodic harmonic maps have a degenerate Dirichlet energy form {g:?}"
        )));
    }
    let dot = |p: [i64; 2], q: [i64; 2]| {
        let (p, q) = (p.map(|x| x as f64), q.map(|x| x as f64));
        p[0] * (g[0][0] * q[0] + g[0][1] * q[1]) + p[1] * (g[1][0] * q[0] + g[1][1] * q[1])
    };
    let (mut b1, mut b2) = ([1i64, 0], [0i64, 1]);
    for _ in 0..MAX_STEPS {
        if dot(b2, b2) < dot(b1, b1) {
            std::mem::swap(&mut b1, &mut b2);
        }
        // Reduced once |⟨b₁, b₂⟩| ≤ |b₁|²/2 (testing the rounded ratio against 0 instead
        // would cycle on ties).
        let ratio = dot(b1, b2) / dot(b1, b1);
        if ratio.abs() <= 0.5 {
            return Ok([b1, b2]);
        }
        if !(ratio.abs() < 1e12) {
            break;
        }
        let mu = ratio.round() as i64;
        b2 = [b2[0] - mu * b1[0], b2[1] - mu * b1[1]];
    }
    Err(Error::Numerical(format!(
        "the lattice reduction of the Dirichlet energy form {g:?} did not terminate"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn energy(g: [[f64; 2]; 2], p: [[i64; 2]; 2], a: f64, b: f64) -> f64 {
        let q = |v: [i64; 2]| {
            let v = v.map(|x| x as f64);
            v[0] * (g[0][0] * v[0] + g[0][1] * v[1]) + v[1] * (g[1][0] * v[0] + g[1][1] * v[1])
        };
        a * a * q(p[0]) + b * b * q(p[1])
    }

    #[test]
    fn reduced_basis_minimises_the_weighted_energy() {
        // Skewed forms: compare with a brute-force search over small unimodular matrices.
        let forms = [
            [[1.0, 0.0], [0.0, 4.0]],
            [[4.0, 0.0], [0.0, 1.0]],
            [[5.0, 7.0], [7.0, 10.0]],
            [[30.0, -41.0], [-41.0, 56.5]],
            [[2.0, 1.0], [1.0, 2.0]],
        ];
        for g in forms {
            let p = reduced_basis(g).unwrap();
            assert_eq!((p[0][0] * p[1][1] - p[0][1] * p[1][0]).abs(), 1);
            for (a, b) in [(2.0, 1.0), (10.0, 1.0), (1.1, 1.0)] {
                let e = energy(g, p, a, b);
                for i in -12..=12i64 {
                    for j in -12..=12i64 {
                        for k in -12..=12i64 {
                            for l in -12..=12i64 {
                                if (i * l - j * k).abs() == 1 {
                                    let other = energy(g, [[i, j], [k, l]], a, b);
                                    assert!(
                                        e <= other * (1.0 + 1e-12),
                                        "{g:?} {p:?} {i} {j} {k} {l}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn degenerate_forms_are_errors() {
        assert!(reduced_basis([[1.0, 1.0], [1.0, 1.0]]).is_err());
        assert!(reduced_basis([[f64::NAN, 0.0], [0.0, 1.0]]).is_err());
        assert!(reduced_basis([[-1.0, 0.0], [0.0, -1.0]]).is_err());
    }
}
