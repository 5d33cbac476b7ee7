//! The Beltrami-coefficient side of DEQ (DEQ paper §5.1.2–5.1.3): the relaxation of ν by
//! the quasi-conformality terms `α ∫|ν|² + β ∫|∇ν|²` ((5.30)–(5.34), (5.39)–(5.42)), the
//! cut-off (5.43), and the reconstruction of the map by LBS (5.44) with Dirichlet values on
//! the boundary circles.

use super::circle_flow::CircleBoundary;
use crate::fem::VertexFaces;
use crate::qc::cut_off;
use num_complex::Complex64;

/// The cut-off parameter δ of (5.43) (the paper's value).
pub(crate) const CUT_OFF_DELTA: f64 = 0.1;

/// The quasi-conformality descent of ν on the initial domain D⁰.
///
/// The α term's descent direction is `−ν` ((5.31), (5.39)). The β term's is `Δν`
/// ((5.32), (5.40)) with vertex values the plain averages of the face values around each
/// vertex (as under (5.23)). We take Δν as the gradient of the discrete energy (5.32) with
/// respect to the vertex values, `−L ν` with L the cotangent stiffness matrix of D⁰ (no
/// division by the vertex areas): with the division, the explicit step `ν + δt β Δν` is unstable
/// as soon as `δt β` exceeds a fraction of the squared edge length (δt β = 0.005 against
/// squared edges of 10⁻⁴ on the unit disk); without it the step is a light local averaging,
/// stable for `δt β · max_i L_ii < 1` (the step is capped there). The change of the vertex
/// values is carried back to the faces as the mean of the three corners, so β = 0 leaves ν
/// untouched.
pub(crate) struct Relaxation<'a> {
    /// Cotangent weights of D⁰ per face corner (`½ cot θ_c`).
    weights: &'a [[f64; 3]],
    /// Face incidence for the vertex averages.
    incidence: &'a VertexFaces,
    /// Faces.
    faces: &'a [[u32; 3]],
    /// `max_i Σ_j |L_ij|` over the off-diagonal weights, which bounds the stable β step.
    max_diagonal: f64,
}

impl<'a> Relaxation<'a> {
    /// The relaxation on D⁰ with cotangent `weights` (per face corner).
    pub fn new(weights: &'a [[f64; 3]], incidence: &'a VertexFaces, faces: &'a [[u32; 3]]) -> Self {
        let mut diag = vec![0.0f64; incidence.n_vertices()];
        for (f, w) in faces.iter().zip(weights) {
            for c in 0..3 {
                diag[f[(c + 1) % 3] as usize] += w[c].abs();
                diag[f[(c + 2) % 3] as usize] += w[c].abs();
            }
        }
        Self {
            weights,
            incidence,
            faces,
            max_diagonal: diag.into_iter().fold(0.0, f64::max),
        }
    }

    /// `ν̃ = ν_pred − decay · ν₀` (DEQ: decay = h α), plus the β step `−smoothing · L ν̃` at
    /// the vertices (DEQ: smoothing = h β), then cut off by (5.43).
    pub fn apply(
        &self,
        predicted: &[Complex64],
        nu0: &[Complex64],
        decay: f64,
        smoothing: f64,
    ) -> Vec<Complex64> {
        let zero = Complex64::new(0.0, 0.0);
        let mut nu: Vec<Complex64> = predicted
            .iter()
            .zip(nu0)
            .map(|(p, n)| if p.is_finite() { p - n * decay } else { *p })
            .collect();
        if smoothing > 0.0 {
            let finite: Vec<Complex64> = nu
                .iter()
                .map(|z| if z.is_finite() { *z } else { zero })
                .collect();
            let re: Vec<f64> = finite.iter().map(|z| z.re).collect();
            let im: Vec<f64> = finite.iter().map(|z| z.im).collect();
            let (vre, vim) = (self.incidence.average(&re), self.incidence.average(&im));
            let mut lap = vec![zero; vre.len()];
            for (f, w) in self.faces.iter().zip(self.weights) {
                for c in 0..3 {
                    let (a, b) = (f[(c + 1) % 3] as usize, f[(c + 2) % 3] as usize);
                    let d = Complex64::new(vre[a] - vre[b], vim[a] - vim[b]) * w[c];
                    lap[a] += d;
                    lap[b] -= d;
                }
            }
            let s = if self.max_diagonal > 0.0 {
                smoothing.min(0.5 / self.max_diagonal)
            } else {
                0.0
            };
            for (z, f) in nu.iter_mut().zip(self.faces) {
                if !z.is_finite() {
                    continue;
                }
                let d: Complex64 = f.iter().map(|&v| lap[v as usize]).sum();
                *z -= d * (s / 3.0);
            }
        }
        nu.into_iter().map(|z| cut_off(z, CUT_OFF_DELTA)).collect()
    }
}

/// Moves boundary vertices along their circles by the tangential part of `dt · velocity`
/// (the Neumann condition of §5.1.3: the boundary shapes stay, the vertices slide), then
/// projects them onto the circle. The slides of a loop are scaled down together, when needed,
/// so that no boundary edge shrinks to less than half its length: no vertex overtakes a
/// neighbour, while a loop turning as a whole keeps pace with the interior next to it.
pub(crate) fn slide_boundary(
    x: &mut [[f64; 3]],
    velocity: &[[f64; 2]],
    dt: f64,
    boundary: &CircleBoundary,
) {
    for (lp, circle) in boundary.loops.iter().zip(&boundary.circles) {
        let n = lp.len();
        let slide: Vec<f64> = lp
            .iter()
            .map(|&v| {
                let t = circle.tangent(x[v as usize]);
                dt * (velocity[v as usize][0] * t[0] + velocity[v as usize][1] * t[1])
            })
            .collect();
        // Arc gaps along the loop's direction of travel (the loop may run either way round).
        let angle = |v: u32| {
            let p = x[v as usize];
            (p[1] - circle.center[1]).atan2(p[0] - circle.center[0])
        };
        let mut scale = 1.0f64;
        for i in 0..n {
            let j = (i + 1) % n;
            let mut gap = angle(lp[j]) - angle(lp[i]);
            gap -= std::f64::consts::TAU * (gap / std::f64::consts::TAU).round();
            let arc = gap * circle.radius;
            // The signed change of the gap, in the same orientation as `arc`.
            let change = slide[j] - slide[i];
            if arc != 0.0 && change / arc < -0.5 {
                scale = scale.min(-0.5 / (change / arc));
            }
        }
        let moves: Vec<[f64; 3]> = lp
            .iter()
            .zip(&slide)
            .map(|(&v, s)| {
                let p = x[v as usize];
                let t = circle.tangent(p);
                let s = s * scale;
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
    use crate::generate::annulus;
    use crate::methods::circle_flow::Circle;

    /// The operators a [`Relaxation`] borrows, on an annulus of `rings` × `sectors` cells.
    fn relaxation_parts(
        rings: usize,
        sectors: usize,
    ) -> (crate::TriMesh, VertexFaces, Vec<[f64; 3]>) {
        let m = annulus(0.4, 1.0, rings, sectors).unwrap();
        let incidence = VertexFaces::new(m.n_vertices(), &m.faces);
        let weights = crate::fem::cotangent_weights(&m.positions, &m.faces);
        (m, incidence, weights)
    }

    #[test]
    fn relaxation_decays_and_cuts_off() {
        let (m, incidence, weights) = relaxation_parts(4, 32);
        let r = Relaxation::new(&weights, &incidence, &m.faces);
        let nu0 = vec![Complex64::new(0.5, 0.0); m.n_faces()];
        let mut pred = nu0.clone();
        pred[3] = Complex64::new(0.0, 2.0);
        let out = r.apply(&pred, &nu0, 0.01, 0.0);
        assert!((out[0].re - 0.5 * (1.0 - 0.01)).abs() < 1e-15);
        assert!(out[3].norm() < 1.0 && out[3].norm() > 0.9);
    }

    #[test]
    fn smoothing_keeps_constants_and_damps_oscillations() {
        let (m, incidence, weights) = relaxation_parts(6, 48);
        let r = Relaxation::new(&weights, &incidence, &m.faces);
        let c = vec![Complex64::new(0.2, -0.3); m.n_faces()];
        for z in r.apply(&c, &c, 0.0, 0.05) {
            assert!((z - Complex64::new(0.2, -0.3)).norm() < 1e-12);
        }
        let wave: Vec<Complex64> = (0..m.n_faces())
            .map(|f| Complex64::new(if f % 2 == 0 { 0.3 } else { -0.3 }, 0.0))
            .collect();
        let energy = |v: &[Complex64]| v.iter().map(|z| z.norm_sqr()).sum::<f64>();
        assert!(energy(&r.apply(&wave, &wave, 0.0, 0.05)) <= energy(&wave) + 1e-12);
    }

    fn annulus_boundary() -> (crate::TriMesh, CircleBoundary) {
        let m = annulus(0.5, 1.0, 3, 24).unwrap();
        let topo = crate::mesh::topology::topology(&m);
        // Both loops have 24 vertices: put the outer one (radius 1) first.
        let mut loops = topo.boundary_loops.clone();
        let r = |l: &Vec<u32>| m.positions[l[0] as usize][0].hypot(m.positions[l[0] as usize][1]);
        loops.sort_by(|a, b| r(b).total_cmp(&r(a)));
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
        let b = CircleBoundary::new(m.n_vertices(), loops, circles);
        (m, b)
    }

    #[test]
    fn sliding_keeps_vertices_on_their_circle_and_in_order() {
        let (m, b) = annulus_boundary();
        let mut x = m.positions.clone();
        // Neighbours sliding towards each other: unlimited, they would meet and cross.
        let v: Vec<[f64; 2]> = (0..x.len())
            .map(|i| {
                let p = x[i];
                let s = if i % 2 == 0 { 10.0 } else { -10.0 };
                [-p[1] * s, p[0] * s]
            })
            .collect();
        let angle = |p: [f64; 3]| p[1].atan2(p[0]);
        let before: Vec<f64> = b.loops[0].iter().map(|&i| angle(x[i as usize])).collect();
        slide_boundary(&mut x, &v, 1.0, &b);
        for (lp, c) in b.loops.iter().zip(&b.circles) {
            for &i in lp {
                let p = x[i as usize];
                assert!((p[0].hypot(p[1]) - c.radius).abs() < 1e-14);
            }
        }
        // Every gap of the outer loop keeps at least half its length, in the same direction.
        let n = before.len();
        let wrap = |d: f64| d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
        for k in 0..n {
            let (i, j) = (b.loops[0][k] as usize, b.loops[0][(k + 1) % n] as usize);
            let old = wrap(before[(k + 1) % n] - before[k]);
            let new = wrap(angle(x[j]) - angle(x[i]));
            assert!(new / old >= 0.5 - 1e-9, "gap {k}: {old} -> {new}");
        }
    }

    #[test]
    fn a_loop_turning_as_a_whole_slides_freely() {
        let (m, b) = annulus_boundary();
        let mut x = m.positions.clone();
        let v: Vec<[f64; 2]> = x.iter().map(|p| [-p[1] * 0.3, p[0] * 0.3]).collect();
        slide_boundary(&mut x, &v, 1.0, &b);
        // Every vertex turns by its arc length 0.3 r / r = 0.3 rad... on the outer circle
        // (tangential speed 0.3, radius 1) and 0.15 / 0.5 = 0.3 rad on the inner one.
        for (&i, p0) in b.loops[0].iter().map(|i| (i, m.positions[*i as usize])) {
            let d = x[i as usize][1].atan2(x[i as usize][0]) - p0[1].atan2(p0[0]);
            let d = d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
            assert!((d - 0.3).abs() < 0.05, "{d}");
        }
    }
}
