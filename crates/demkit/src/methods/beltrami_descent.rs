//! The Beltrami-coefficient side of DEQ (DEQ paper §5.1.2–5.1.3): the relaxation of ν by
//! the quasi-conformality terms `α ∫|ν|² + β ∫|∇ν|²` ((5.30)–(5.34), (5.39)–(5.42)), the
//! cut-off (5.43), and the reconstruction of the map by LBS (5.44) with Dirichlet values on
//! the boundary circles.

use super::circle_flow::CircleBoundary;
use crate::fem::{DiffusionFactor, VertexFaces};
use crate::geometry::signed_area_2d;
use crate::qc::cut_off;
use num_complex::Complex64;

/// The cut-off parameter δ of (5.43) (the paper's value).
pub(crate) const CUT_OFF_DELTA: f64 = 0.1;

/// The quasi-conformality descent of ν on the initial domain D⁰.
///
/// The α term's descent direction is `−ν` ((5.31), (5.39)). The β term's is `Δν`
/// ((5.32), (5.40)) with vertex values the plain averages of the face values around each
/// vertex (as under (5.23)); it is taken implicitly, `(A + δt β L) ν̄ = A ν` on D⁰, because the
/// explicit step `ν + δt β Δν` is unstable as soon as `δt β` exceeds a fraction of the squared
/// edge length (δt β = 0.005 against edges of 0.01–0.02 on the unit disk). Only the change
/// `ν̄ − ν` at the vertices is carried back to the faces (the mean of the three corners), so
/// β = 0 leaves ν untouched.
pub(crate) struct Relaxation<'a> {
    /// The factor of `A + t β L` on D⁰ (t = δt for DEQ).
    pub smoothing: Option<DiffusionFactor<'a>>,
    /// Face incidence for the vertex averages.
    pub incidence: &'a VertexFaces,
    /// Faces.
    pub faces: &'a [[u32; 3]],
}

impl Relaxation<'_> {
    /// `ν̃ = ν_pred − decay · ν₀` (DEQ: decay = h α), then smoothed by the β term, then cut
    /// off by (5.43). A step `h = fraction × δt` smooths proportionally less: the smoothing
    /// increment is scaled by `fraction`, its first-order value for the shorter time.
    pub fn apply(
        &self,
        predicted: &[Complex64],
        nu0: &[Complex64],
        decay: f64,
        fraction: f64,
    ) -> Vec<Complex64> {
        let mut nu: Vec<Complex64> = predicted
            .iter()
            .zip(nu0)
            .map(|(p, n)| if p.is_finite() { p - n * decay } else { *p })
            .collect();
        if let Some(s) = &self.smoothing {
            let finite: Vec<Complex64> = nu
                .iter()
                .map(|z| if z.is_finite() { *z } else { Complex64::new(0.0, 0.0) })
                .collect();
            let re: Vec<f64> = finite.iter().map(|z| z.re).collect();
            let im: Vec<f64> = finite.iter().map(|z| z.im).collect();
            let (vre, vim) = (self.incidence.average(&re), self.incidence.average(&im));
            let smooth = |v: &[f64]| {
                let mut b: Vec<f64> = v.iter().zip(&s.mass).map(|(x, m)| x * m).collect();
                s.factor.solve_in_place(&mut b);
                b
            };
            let (sre, sim) = (smooth(&vre), smooth(&vim));
            for (z, f) in nu.iter_mut().zip(self.faces) {
                if !z.is_finite() {
                    continue;
                }
                let d: Complex64 = f
                    .iter()
                    .map(|&v| {
                        let v = v as usize;
                        Complex64::new(sre[v] - vre[v], sim[v] - vim[v])
                    })
                    .sum();
                *z += d * (fraction / 3.0);
            }
        }
        nu.into_iter().map(|z| cut_off(z, CUT_OFF_DELTA)).collect()
    }
}

/// Number of faces of the planar map `x` with signed area ≤ 0.
pub(crate) fn count_flips(x: &[[f64; 3]], faces: &[[u32; 3]]) -> usize {
    faces
        .iter()
        .filter(|f| {
            let [a, b, c] = f.map(|v| x[v as usize]);
            !(signed_area_2d(a, b, c) > 0.0)
        })
        .count()
}

/// Moves boundary vertices along their circles by the tangential part of `dt · velocity`
/// (the Neumann condition of §5.1.3: the boundary shapes stay, the vertices slide), each by at
/// most `SLIDE_LIMIT` of its shorter boundary edge so that no vertex overtakes a neighbour,
/// then projects them onto the circle.
pub(crate) fn slide_boundary(
    x: &mut [[f64; 3]],
    velocity: &[[f64; 2]],
    dt: f64,
    boundary: &CircleBoundary,
) {
    const SLIDE_LIMIT: f64 = 0.4;
    for (lp, circle) in boundary.loops.iter().zip(&boundary.circles) {
        let n = lp.len();
        let moves: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let v = lp[i] as usize;
                let p = x[v];
                let prev = x[lp[(i + n - 1) % n] as usize];
                let next = x[lp[(i + 1) % n] as usize];
                let dist = |a: [f64; 3]| (a[0] - p[0]).hypot(a[1] - p[1]);
                let limit = SLIDE_LIMIT * dist(prev).min(dist(next));
                let t = circle.tangent(p);
                let s = (dt * (velocity[v][0] * t[0] + velocity[v][1] * t[1])).clamp(-limit, limit);
                circle.project([p[0] + s * t[0], p[1] + s * t[1], 0.0])
            })
            .collect();
        for (&v, m) in lp.iter().zip(moves) {
            x[v as usize] = m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::DiffusionOperator;
    use crate::generate::annulus;
    use crate::geometry::face_areas;
    use crate::methods::circle_flow::Circle;

    #[test]
    fn relaxation_decays_and_cuts_off() {
        let m = annulus(0.4, 1.0, 4, 32).unwrap();
        let incidence = VertexFaces::new(m.n_vertices(), &m.faces);
        let r = Relaxation {
            smoothing: None,
            incidence: &incidence,
            faces: &m.faces,
        };
        let nu0 = vec![Complex64::new(0.5, 0.0); m.n_faces()];
        let mut pred = nu0.clone();
        pred[3] = Complex64::new(0.0, 2.0);
        let out = r.apply(&pred, &nu0, 0.01, 1.0);
        assert!((out[0].re - 0.5 * (1.0 - 0.01)).abs() < 1e-15);
        assert!(out[3].norm() < 1.0 && out[3].norm() > 0.9);
    }

    #[test]
    fn smoothing_keeps_constants_and_damps_oscillations() {
        let m = annulus(0.4, 1.0, 6, 48).unwrap();
        let incidence = VertexFaces::new(m.n_vertices(), &m.faces);
        let op = DiffusionOperator::new(m.n_vertices(), &m.faces).unwrap();
        let areas = face_areas(&m.positions, &m.faces);
        let r = Relaxation {
            smoothing: Some(op.factor(&m.positions, &areas, 0.05, &[]).unwrap()),
            incidence: &incidence,
            faces: &m.faces,
        };
        let c = vec![Complex64::new(0.2, -0.3); m.n_faces()];
        for z in r.apply(&c, &c, 0.0, 1.0) {
            assert!((z - Complex64::new(0.2, -0.3)).norm() < 1e-12);
        }
        let wave: Vec<Complex64> = (0..m.n_faces())
            .map(|f| Complex64::new(if f % 2 == 0 { 0.3 } else { -0.3 }, 0.0))
            .collect();
        let energy = |v: &[Complex64]| v.iter().map(|z| z.norm_sqr()).sum::<f64>();
        assert!(energy(&r.apply(&wave, &wave, 0.0, 1.0)) <= energy(&wave) + 1e-12);
    }

    #[test]
    fn sliding_keeps_vertices_on_their_circle_and_in_order() {
        let m = annulus(0.5, 1.0, 3, 24).unwrap();
        let topo = crate::mesh::topology::topology(&m);
        let circles = vec![
            Circle {
                center: [0.0, 0.0],
                radius: 1.0,
            },
            Circle {
                center: [0.0, 0.0],
                radius: 0.5,
            },
        ];
        // Both loops have 24 vertices: put the outer one (radius 1) first.
        let mut loops = topo.boundary_loops.clone();
        loops.sort_by(|a, b| {
            let r = |l: &Vec<u32>| m.positions[l[0] as usize][0].hypot(m.positions[l[0] as usize][1]);
            r(b).total_cmp(&r(a))
        });
        let b = CircleBoundary::new(m.n_vertices(), loops, circles);
        let mut x = m.positions.clone();
        assert_eq!(count_flips(&x, &m.faces), 0);
        // A strong swirl: without the limit vertices would overtake each other.
        let v: Vec<[f64; 2]> = x.iter().map(|p| [-p[1] * 10.0, p[0] * 10.0]).collect();
        slide_boundary(&mut x, &v, 1.0, &b);
        for (lp, c) in b.loops.iter().zip(&b.circles) {
            for &i in lp {
                let p = x[i as usize];
                assert!((p[0].hypot(p[1]) - c.radius).abs() < 1e-14);
            }
        }
        assert_eq!(count_flips(&x, &m.faces), 0);
    }
}
