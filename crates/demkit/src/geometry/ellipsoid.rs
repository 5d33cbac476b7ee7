//! The ellipsoid x²/a² + y²/b² + z²/c² = 1 with its axes along x, y, z (the EDEM paper's
//! target domain, Lyu, Lui & Choi 2026, §3), and the unit sphere as its case a = b = c = 1.
//!
//! Maps onto it are handled through the linear map `M = diag(a, b, c)`, which carries the unit
//! sphere onto the ellipsoid:
//! - points are brought back onto it along their ray from the centre ([`Ellipsoid::project`]),
//!   as the paper renormalizes after every move;
//! - the orientation test of the sphere, `((q − p) × (r − p)) · (p + q + r) > 0`, is the same on
//!   the ellipsoid: for any diagonal `M` with positive entries the test of `Mp, Mq, Mr` is the
//!   test of `p, q, r` times `det M > 0` (the cross product transforms by `det M · M⁻ᵀ`, and
//!   `M⁻ᵀ = M⁻¹` here). So one flip predicate serves both, and the sphere's bijectivity
//!   correction applies to the ellipsoid's map through `M⁻¹` ([`Ellipsoid::to_sphere`]).

use super::vec3::{add, dot, scale};
use crate::{Error, Result};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The largest ratio of two radii that a map is computed for: beyond it the conformal factor
/// of the ellipsoid's map spans more than double precision can hold between its poles.
pub const MAX_ASPECT: f64 = 1e3;

/// An ellipsoid centred at the origin with semi-axes `a`, `b`, `c` along x, y, z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid {
    radii: [f64; 3],
    /// `1 / radius` per axis.
    inverse: [f64; 3],
    /// `(m / radius) / radius` per axis, m the least radius: proportional to the quadric's
    /// coefficients 1/radius², and of unit size whatever the radii.
    normal_weights: [f64; 3],
}

impl Ellipsoid {
    /// The unit sphere.
    pub const UNIT_SPHERE: Ellipsoid = Ellipsoid {
        radii: [1.0; 3],
        inverse: [1.0; 3],
        normal_weights: [1.0; 3],
    };

    /// The ellipsoid with radii `a`, `b`, `c`: each a positive finite (normal) number, and no
    /// two further apart than [`MAX_ASPECT`]; anything else is an argument error naming the
    /// radii. Any size works: maps are computed on the ellipsoid scaled by a power of two
    /// ([`Ellipsoid::normalizing_exponent`]).
    pub fn new(a: f64, b: f64, c: f64) -> Result<Self> {
        let radii = [a, b, c];
        if !radii
            .iter()
            .all(|r| r.is_finite() && *r >= f64::MIN_POSITIVE)
        {
            return Err(Error::Argument(format!(
                "an ellipsoid needs radii that are positive finite numbers, got {a}:{b}:{c}"
            )));
        }
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        if hi / lo > MAX_ASPECT {
            return Err(Error::Argument(format!(
                "the ellipsoid's radii {a}:{b}:{c} are {:.3e} times apart; at most {MAX_ASPECT} \
                 is mapped",
                hi / lo
            )));
        }
        Ok(Self::of_radii(radii))
    }

    /// The ellipsoid of checked radii.
    fn of_radii(radii: [f64; 3]) -> Self {
        let least = radii[0].min(radii[1]).min(radii[2]);
        Self {
            radii,
            inverse: radii.map(|r| 1.0 / r),
            normal_weights: radii.map(|r| (least / r) / r),
        }
    }

    /// The radii `[a, b, c]`.
    pub fn radii(&self) -> [f64; 3] {
        self.radii
    }

    /// True for the unit sphere.
    pub fn is_unit_sphere(&self) -> bool {
        self.radii == [1.0; 3]
    }

    /// The same ellipsoid with every radius multiplied by 2^k (exact).
    pub fn scaled_by_power_of_two(&self, k: i32) -> Self {
        Self::of_radii(self.radii.map(|r| crate::mesh::scale::ldexp(r, k)))
    }

    /// The exponent k by which to scale the radii before computing on the ellipsoid (areas and
    /// their products far from overflow and underflow), as for meshes
    /// ([`crate::mesh::scale::normalizing_exponent`]): 0 for radii within 2^±40.
    pub fn normalizing_exponent(&self) -> i32 {
        crate::mesh::scale::normalizing_exponent(&[self.radii])
    }

    /// `x²/a² + y²/b² + z²/c²`, as `(x/a)² + (y/b)² + (z/c)²` (no overflow for huge radii): 1
    /// on the ellipsoid, below 1 inside.
    #[inline]
    pub fn quadric(&self, p: [f64; 3]) -> f64 {
        let u = self.to_sphere(p);
        u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    }

    /// `|x²/a² + y²/b² + z²/c² − 1|`: how far `p` is from the ellipsoid, relative to its size.
    pub fn residual(&self, p: [f64; 3]) -> f64 {
        (self.quadric(p) - 1.0).abs()
    }

    /// The point of the ellipsoid on the ray from the centre through `p` (the origin stays
    /// put): `p / √(x²/a² + y²/b² + z²/c²)`, computed without overflow or underflow for points
    /// of any size.
    #[inline]
    pub fn project(&self, p: [f64; 3]) -> [f64; 3] {
        let q = self.quadric(p);
        if q > 1e-200 && q < 1e200 {
            return scale(p, 1.0 / q.sqrt());
        }
        // Far from unit size: the quadric of p divided by its largest term's root.
        let u = self.to_sphere(p);
        let m = u[0].abs().max(u[1].abs()).max(u[2].abs());
        if !(m > 0.0 && m.is_finite()) {
            return p;
        }
        let r = (u[0] / m).hypot(u[1] / m).hypot(u[2] / m);
        scale(scale(p, 1.0 / m), 1.0 / r)
    }

    /// The outward unit normal of the ellipsoid at the point where the ray through `p` meets
    /// it: `(x/a², y/b², z/c²)` normalized.
    #[inline]
    pub fn normal(&self, p: [f64; 3]) -> [f64; 3] {
        let w = self.normal_weights;
        super::sphere::normalize([w[0] * p[0], w[1] * p[1], w[2] * p[2]])
    }

    /// `v` minus its component along the normal at `p`: the tangential part of a velocity (the
    /// SDEM paper's (3.13), on the ellipsoid).
    #[inline]
    pub fn tangential(&self, v: [f64; 3], p: [f64; 3]) -> [f64; 3] {
        let n = self.normal(p);
        add(v, scale(n, -dot(v, n)))
    }

    /// `M⁻¹ p = (x/a, y/b, z/c)`: the ellipsoid onto the unit sphere.
    #[inline]
    pub fn to_sphere(&self, p: [f64; 3]) -> [f64; 3] {
        let s = self.inverse;
        [p[0] * s[0], p[1] * s[1], p[2] * s[2]]
    }

    /// `M u = (a x, b y, c z)`: the unit sphere onto the ellipsoid.
    #[inline]
    pub fn from_sphere(&self, u: [f64; 3]) -> [f64; 3] {
        let r = self.radii;
        [u[0] * r[0], u[1] * r[1], u[2] * r[2]]
    }

    /// The surface area, `∫∫ √(b²c²(1 − t²)cos²φ + a²c²(1 − t²)sin²φ + a²b²t²) dφ dt` over
    /// t = cos θ ∈ [−1, 1], φ ∈ [0, 2π) (Gauss–Legendre in t, the trapezoidal rule in φ: to
    /// about 1e-10 for radii 1:4 apart); a sphere's 4πr² exactly.
    pub fn area(&self) -> f64 {
        let [a, b, c] = self.radii;
        if a == b && b == c {
            return 4.0 * std::f64::consts::PI * a * a;
        }
        let (nodes, weights) = gauss_legendre_64();
        const N_PHI: usize = 256;
        let mut total = 0.0;
        for (t, w) in nodes.iter().zip(&weights) {
            let ring: f64 = (0..N_PHI)
                .map(|k| self.area_element(*t, TAU * k as f64 / N_PHI as f64))
                .sum();
            total += w * ring * TAU / N_PHI as f64;
        }
        total
    }

    /// The area element of the parameterization `(a √(1 − t²) cos φ, b √(1 − t²) sin φ, c t)`
    /// at (t, φ): `dA = √(b²c²(1 − t²)cos²φ + a²c²(1 − t²)sin²φ + a²b²t²) dt dφ`.
    fn area_element(&self, t: f64, phi: f64) -> f64 {
        let [a, b, c] = self.radii;
        let s2 = 1.0 - t * t;
        let (sp, cp) = phi.sin_cos();
        (b * b * c * c * s2 * cp * cp + a * a * c * c * s2 * sp * sp + a * a * b * b * t * t).sqrt()
    }

    /// `n` points spread evenly by area over the ellipsoid, given as their images on the unit
    /// sphere ([`Ellipsoid::to_sphere`]): the Fibonacci lattice (`u_k = (k + ½)/n`, `v_k` the
    /// fractional part of `k` times the golden angle's share of a turn) carried through the
    /// inverse distribution functions of the area element in t and then in φ, so that every
    /// point has the same share of the ellipsoid's area. On a sphere, the Fibonacci sphere
    /// ([`super::sphere::fibonacci_sphere`]) itself.
    pub fn equal_area_points(&self, n: usize) -> Vec<[f64; 3]> {
        let [a, b, c] = self.radii;
        if a == b && b == c {
            return super::sphere::fibonacci_sphere(n);
        }
        // The marginal distribution of t, tabulated.
        const N_T: usize = 4096;
        const N_PHI: usize = 256;
        let ring = |t: f64| -> f64 {
            (0..N_PHI)
                .map(|k| self.area_element(t, TAU * (k as f64 + 0.5) / N_PHI as f64))
                .sum::<f64>()
        };
        let ts: Vec<f64> = (0..=N_T)
            .map(|i| -1.0 + 2.0 * i as f64 / N_T as f64)
            .collect();
        let density: Vec<f64> = ts.iter().map(|&t| ring(t)).collect();
        let mut cdf = vec![0.0; N_T + 1];
        for i in 1..=N_T {
            cdf[i] = cdf[i - 1] + 0.5 * (density[i - 1] + density[i]);
        }
        let total = cdf[N_T];
        let golden_share = (3.0 - 5f64.sqrt()) / 2.0;
        (0..n)
            .into_par_iter()
            .map(|k| {
                let t = invert(&ts, &cdf, total * (k as f64 + 0.5) / n as f64);
                // The conditional distribution of φ at t.
                let phis: Vec<f64> = (0..=N_PHI).map(|j| TAU * j as f64 / N_PHI as f64).collect();
                let mut c = vec![0.0; N_PHI + 1];
                for j in 1..=N_PHI {
                    c[j] = c[j - 1]
                        + 0.5 * (self.area_element(t, phis[j - 1]) + self.area_element(t, phis[j]));
                }
                let share = (k as f64 * golden_share).fract();
                let phi = invert(&phis, &c, c[N_PHI] * share);
                let r = (1.0 - t * t).max(0.0).sqrt();
                let (sp, cp) = phi.sin_cos();
                [r * cp, r * sp, t]
            })
            .collect()
    }
}

/// The x at which the increasing piecewise-linear function through `(xs[i], ys[i])` takes the
/// value `y` (clamped to the ends).
fn invert(xs: &[f64], ys: &[f64], y: f64) -> f64 {
    let i = ys.partition_point(|&v| v < y).clamp(1, ys.len() - 1);
    let (y0, y1) = (ys[i - 1], ys[i]);
    let s = if y1 > y0 {
        ((y - y0) / (y1 - y0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    xs[i - 1] + s * (xs[i] - xs[i - 1])
}

/// Nodes and weights of the 64-point Gauss–Legendre rule on [−1, 1], by Newton's iteration on
/// the Legendre polynomial from the Chebyshev-like initial guesses.
fn gauss_legendre_64() -> ([f64; 64], [f64; 64]) {
    const N: usize = 64;
    let mut x = [0.0; N];
    let mut w = [0.0; N];
    for i in 0..N {
        let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (N as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_N(t) and its derivative by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, t);
            for k in 2..=N {
                let p2 = ((2 * k - 1) as f64 * t * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = N as f64 * (t * p1 - p0) / (t * t - 1.0);
            let dt = p1 / dp;
            t -= dt;
            if dt.abs() < 1e-16 {
                break;
            }
        }
        x[i] = t;
        w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
    (x, w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::{normalize, spherical_orientation};
    use crate::geometry::{cross, sub};

    #[test]
    fn radii_must_be_positive_finite_and_in_range() {
        for (a, b, c) in [
            (0.0, 1.0, 1.0),
            (-1.0, 1.0, 1.0),
            (f64::NAN, 1.0, 1.0),
            (1.0, f64::INFINITY, 1.0),
            (1e-310, 1.0, 1.0),
            (1.0, 1.0, 1e4),
        ] {
            assert!(Ellipsoid::new(a, b, c).is_err(), "{a}:{b}:{c}");
        }
        assert!(Ellipsoid::new(1.0, 2.0, 4.0).is_ok());
        let huge = Ellipsoid::new(1e300, 2e300, 3e300).unwrap();
        let k = huge.normalizing_exponent();
        assert!(k < -900);
        let unit = huge.scaled_by_power_of_two(k);
        assert!(unit.radii().iter().all(|r| (0.1..=1.0).contains(r)));
        assert_eq!(
            Ellipsoid::new(1.0, 2.0, 4.0)
                .unwrap()
                .normalizing_exponent(),
            0
        );
    }

    #[test]
    fn projection_lands_on_the_ellipsoid_along_the_ray() {
        let e = Ellipsoid::new(1.0, 0.6, 2.0).unwrap();
        for i in 0..100 {
            let t = i as f64 * 0.731;
            let p = [t.sin() * 3.0, (1.3 * t).cos() - 0.2, (0.7 * t).sin() * 0.4];
            let q = e.project(p);
            assert!(e.residual(q) < 1e-15, "{}", e.residual(q));
            // On the same ray: q = s p with s > 0.
            let s = dot(q, p) / dot(p, p);
            assert!(s > 0.0);
            assert!(crate::geometry::norm(sub(q, scale(p, s))) < 1e-14);
        }
        // Points of any size land on it.
        let huge = Ellipsoid::new(1e300, 2e300, 3e300).unwrap();
        for p in [[1.0, 2.0, 3.0], [1e-300, 0.0, 2e-300], [1e305, -1e306, 0.0]] {
            assert!(e.residual(e.project(p)) < 1e-15, "{p:?}");
        }
        for p in [[1.0, 2.0, 3.0], [1e100, 0.0, 2e100], [1e305, -1e306, 0.0]] {
            assert!(huge.residual(huge.project(p)) < 1e-15, "{p:?}");
        }
    }

    #[test]
    fn the_normal_is_the_gradient_of_the_quadric() {
        let e = Ellipsoid::new(1.0, 2.0, 4.0).unwrap();
        let p = e.project([0.3, -0.5, 0.8]);
        let n = e.normal(p);
        // Finite differences of the quadric at p point along n.
        let h = 1e-6;
        let g: [f64; 3] = std::array::from_fn(|k| {
            let mut q = p;
            q[k] += h;
            let mut r = p;
            r[k] -= h;
            (e.quadric(q) - e.quadric(r)) / (2.0 * h)
        });
        let g = normalize(g);
        assert!(crate::geometry::norm(sub(g, n)) < 1e-8);
        // A tangential vector has no normal component.
        let v = e.tangential([1.0, 2.0, 3.0], p);
        assert!(dot(v, n).abs() < 1e-14);
    }

    #[test]
    fn the_orientation_test_is_the_spheres_through_the_axis_map() {
        let e = Ellipsoid::new(1.0, 0.5, 3.0).unwrap();
        for i in 0..50 {
            let t = i as f64 * 1.37;
            let p = normalize([t.cos(), t.sin(), 0.3 * t.cos()]);
            let q = normalize([(t + 0.2).cos(), (t + 0.1).sin(), 0.1]);
            let r = normalize([0.2, -0.4, (2.0 * t).cos()]);
            let on_sphere = spherical_orientation(p, q, r);
            let [ep, eq, er] = [p, q, r].map(|x| e.from_sphere(x));
            let on_ellipsoid = dot(cross(sub(eq, ep), sub(er, ep)), add(add(ep, eq), er)) / 3.0;
            let det_m = 1.0 * 0.5 * 3.0;
            assert!((on_ellipsoid - det_m * on_sphere).abs() < 1e-12 * (1.0 + on_sphere.abs()));
            let back = e.to_sphere(ep);
            assert!(crate::geometry::norm(sub(back, p)) < 1e-15);
        }
    }

    #[test]
    fn equal_area_points_share_the_area_evenly() {
        // Count the points in a band of the ellipsoid: their share of the points is the band's
        // share of the area (measured by a fine quadrature of the area element).
        let e = Ellipsoid::new(1.0, 1.5, 3.0).unwrap();
        let n = 20000;
        let points = e.equal_area_points(n);
        assert_eq!(points.len(), n);
        for p in &points {
            assert!((crate::geometry::norm(*p) - 1.0).abs() < 1e-12);
        }
        let band = |lo: f64, hi: f64| {
            let m = 2000;
            let mut s = 0.0;
            for i in 0..m {
                let t = lo + (hi - lo) * (i as f64 + 0.5) / m as f64;
                for j in 0..256 {
                    s += e.area_element(t, TAU * (j as f64 + 0.5) / 256.0);
                }
            }
            s * (hi - lo) / m as f64 * TAU / 256.0 / e.area()
        };
        for (lo, hi) in [(-1.0, -0.8), (-0.2, 0.3), (0.9, 1.0)] {
            let share = points.iter().filter(|p| p[2] >= lo && p[2] < hi).count() as f64 / n as f64;
            assert!(
                (share - band(lo, hi)).abs() < 2e-3,
                "{lo}..{hi}: {share} {}",
                band(lo, hi)
            );
        }
        // A wedge of longitudes, where x and y differ.
        let wedge = points
            .iter()
            .filter(|p| p[1].atan2(p[0]).abs() < 0.3)
            .count() as f64
            / n as f64;
        let exact = {
            let m = 4000;
            let mut s = 0.0;
            for i in 0..m {
                let t = -1.0 + 2.0 * (i as f64 + 0.5) / m as f64;
                for j in 0..200 {
                    s += e.area_element(t, -0.3 + 0.6 * (j as f64 + 0.5) / 200.0);
                }
            }
            s * 2.0 / m as f64 * 0.6 / 200.0 / e.area()
        };
        assert!((wedge - exact).abs() < 2e-3, "{wedge} {exact}");
    }

    #[test]
    fn areas_of_sphere_and_spheroids() {
        assert!((Ellipsoid::UNIT_SPHERE.area() - 4.0 * std::f64::consts::PI).abs() < 1e-13);
        // A prolate spheroid a = b = 1, c = 2: 2πa²(1 + c/(a e) asin e), e² = 1 − a²/c².
        let e = Ellipsoid::new(1.0, 1.0, 2.0).unwrap();
        let ecc = (1.0f64 - 0.25).sqrt();
        let exact = 2.0 * std::f64::consts::PI * (1.0 + 2.0 / ecc * ecc.asin());
        assert!(
            (e.area() - exact).abs() < 1e-10 * exact,
            "{} {exact}",
            e.area()
        );
        // An oblate one a = b = 2, c = 1: 2πa² + π c²/e ln((1 + e)/(1 − e)), e² = 1 − c²/a².
        let e = Ellipsoid::new(2.0, 2.0, 1.0).unwrap();
        let ecc = (1.0f64 - 0.25).sqrt();
        let exact = 2.0 * std::f64::consts::PI * 4.0
            + std::f64::consts::PI / ecc * ((1.0 + ecc) / (1.0 - ecc)).ln();
        assert!(
            (e.area() - exact).abs() < 1e-10 * exact,
            "{} {exact}",
            e.area()
        );
        // Scaling by 2 multiplies the area by 4.
        let e = Ellipsoid::new(1.0, 2.0, 4.0).unwrap();
        let s = e.scaled_by_power_of_two(1);
        assert!((s.area() - 4.0 * e.area()).abs() < 1e-12 * s.area());
    }
}
