//! Geometry modification of the circle domain (DEQ paper §5.1.2, Alg. 5.1): how the centre,
//! radius and rotation of every hole should move, from the density velocity at its vertices
//! ((5.9)–(5.17)) and the Beltrami terms of the faces around it ((5.18)–(5.27)), combined by
//! (5.28). The domain is then rebuilt by LBS from the relaxed ν ((5.29)–(5.34); see
//! `beltrami_descent` and `deq`).

use super::circle_flow::CircleBoundary;
use crate::fem::VertexFaces;
use crate::linalg::solve_dense;
use crate::qc::triangle_beltrami_derivatives;
use num_complex::Complex64;

/// The rate of change of one hole: `d/dt` of its centre, radius and rotation angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HoleRate {
    pub center: [f64; 2],
    pub radius: f64,
    pub angle: f64,
}

/// The faces around each hole and the fixed data of D⁰ the hole terms need.
pub(crate) struct HoleTerms<'a> {
    faces: &'a [[u32; 3]],
    source: &'a [[f64; 3]],
    /// Face areas on D⁰.
    source_areas: &'a [f64],
    /// Cotangent weights `½ cot θ_c` of D⁰ per face corner.
    weights: &'a [[f64; 3]],
    /// The faces around each vertex.
    incidence: &'a VertexFaces,
    /// Faces with a vertex on each loop (index = loop).
    ring: Vec<Vec<u32>>,
    alpha: f64,
    beta: f64,
}

impl<'a> HoleTerms<'a> {
    /// Prepares the hole terms for the loops of `boundary` on the source domain D⁰.
    #[allow(clippy::too_many_arguments)] // the fixed data of D⁰, each borrowed from the run
    pub fn new(
        faces: &'a [[u32; 3]],
        source: &'a [[f64; 3]],
        source_areas: &'a [f64],
        weights: &'a [[f64; 3]],
        incidence: &'a VertexFaces,
        boundary: &CircleBoundary,
        alpha: f64,
        beta: f64,
    ) -> Self {
        let mut ring = vec![Vec::new(); boundary.loops.len()];
        for (f, face) in faces.iter().enumerate() {
            let mut seen = [u32::MAX; 3];
            for (k, &v) in face.iter().enumerate() {
                let l = boundary.loop_of[v as usize];
                if l != u32::MAX && !seen.contains(&l) {
                    seen[k] = l;
                    ring[l as usize].push(f as u32);
                }
            }
        }
        Self {
            faces,
            source,
            source_areas,
            weights,
            incidence,
            ring,
            alpha,
            beta,
        }
    }

    /// The descent rate (5.28) `dw = dw¹ + α dw² + β dw³` of every hole (loops 1..; the outer
    /// circle stays the unit circle), for the current map `x` with Beltrami coefficient `nu`
    /// (D⁰ → x, per face) and density velocity `velocity`.
    pub fn rates(
        &self,
        x: &[[f64; 3]],
        nu: &[Complex64],
        velocity: &[[f64; 2]],
        boundary: &CircleBoundary,
    ) -> Vec<HoleRate> {
        (1..boundary.loops.len())
            .map(|l| {
                let lp = &boundary.loops[l];
                let circle = boundary.circles[l];
                let fit = fit_circle_motion(x, velocity, lp, circle.center);
                let (g2, g3) = self.beltrami_gradients(l, x, nu, boundary);
                // (5.19)–(5.21) and (5.24)–(5.26) average over the hole's n_i vertices.
                let n = lp.len() as f64;
                let g: [f64; 4] =
                    std::array::from_fn(|j| (self.alpha * g2[j] + self.beta * g3[j]) / n);
                HoleRate {
                    center: [fit[0] - g[0], fit[1] - g[1]],
                    radius: fit[2] - g[2],
                    angle: fit[3] / circle.radius - g[3],
                }
            })
            .collect()
    }

    /// Gradients of `E²_bdy = Σ Area |ν|²` (5.18) and of `E³_bdy` (5.23) over the faces
    /// around loop `l`, with respect to the hole parameters (c_x, c_y, r, θ): a hole vertex
    /// is `w = c + r e^{i(θ_b + θ)}`, so `∂w/∂c_x = 1`, `∂w/∂c_y = i`, `∂w/∂r = e^{iθ_b}`,
    /// `∂w/∂θ = i (w − c)`. The derivative of ν with respect to the image corners comes from
    /// [`triangle_beltrami_derivatives`]; the vertex values ν(v) are the plain averages over
    /// the faces of v, as below (5.23). Appendix B's (B.11) is garbled in print: this is our
    /// own derivation of the same quantities.
    fn beltrami_gradients(
        &self,
        l: usize,
        x: &[[f64; 3]],
        nu: &[Complex64],
        boundary: &CircleBoundary,
    ) -> ([f64; 4], [f64; 4]) {
        let circle = boundary.circles[l];
        let c = Complex64::new(circle.center[0], circle.center[1]);
        let ring = &self.ring[l];
        // dν_T/dq for every face around the hole.
        let dnu: Vec<[Complex64; 4]> = ring
            .iter()
            .map(|&f| {
                let face = self.faces[f as usize];
                let s = face.map(|v| {
                    let p = self.source[v as usize];
                    [p[0], p[1]]
                });
                let t = face.map(|v| [x[v as usize][0], x[v as usize][1]]);
                let (_, dw) = triangle_beltrami_derivatives(s, t);
                let mut out = [Complex64::new(0.0, 0.0); 4];
                for k in 0..3 {
                    let v = face[k] as usize;
                    if boundary.loop_of[v] != l as u32 {
                        continue;
                    }
                    let w = Complex64::new(x[v][0], x[v][1]);
                    let radial = (w - c) / circle.radius;
                    let dq = [
                        Complex64::new(1.0, 0.0),
                        Complex64::new(0.0, 1.0),
                        radial,
                        Complex64::new(0.0, 1.0) * (w - c),
                    ];
                    for j in 0..4 {
                        out[j] += dw[k] * dq[j];
                    }
                }
                out
            })
            .collect();
        let mut g2 = [0.0; 4];
        for (i, &f) in ring.iter().enumerate() {
            let (a, z) = (self.source_areas[f as usize], nu[f as usize]);
            for j in 0..4 {
                g2[j] += 2.0 * a * (z.conj() * dnu[i][j]).re;
            }
        }
        // Vertex values and their derivatives at the vertices of the ring's faces.
        let mut vertex_dnu: std::collections::HashMap<u32, [Complex64; 4]> =
            std::collections::HashMap::new();
        for (i, &f) in ring.iter().enumerate() {
            for &v in &self.faces[f as usize] {
                let e = vertex_dnu.entry(v).or_insert([Complex64::new(0.0, 0.0); 4]);
                let d = self.incidence.faces_of(v as usize).len() as f64;
                for j in 0..4 {
                    e[j] += dnu[i][j] / d;
                }
            }
        }
        let vertex_nu = |v: u32| {
            let fs = self.incidence.faces_of(v as usize);
            fs.iter().map(|&f| nu[f as usize]).sum::<Complex64>() / fs.len() as f64
        };
        let mut g3 = [0.0; 4];
        for &f in ring {
            let face = self.faces[f as usize];
            for corner in 0..3 {
                let a = face[(corner + 1) % 3];
                let b = face[(corner + 2) % 3];
                let diff = vertex_nu(a) - vertex_nu(b);
                let (da, db) = (vertex_dnu[&a], vertex_dnu[&b]);
                for j in 0..4 {
                    g3[j] +=
                        2.0 * self.weights[f as usize][corner] * (diff.conj() * (da[j] - db[j])).re;
                }
            }
        }
        (g2, g3)
    }
}

/// The least-squares fit (5.12) of the velocity at the hole's vertices by a translation, a
/// radial and a tangential motion: minimises `Σ_b |Δc + p_r u_b + p_T t_b − v_b|²` over
/// (Δc, p_r, p_T), with `u_b`, `t_b` the unit radial and tangent at vertex b. For evenly spaced
/// vertices this is exactly the averages (5.14)–(5.16); the fit stays right when the spacing
/// is uneven. Returns `[Δc_x, Δc_y, p_r, p_T]`.
pub(crate) fn fit_circle_motion(
    x: &[[f64; 3]],
    velocity: &[[f64; 2]],
    lp: &[u32],
    center: [f64; 2],
) -> [f64; 4] {
    let mut m = [[0.0; 4]; 4];
    let mut rhs = [0.0; 4];
    for &v in lp {
        let p = x[v as usize];
        let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
        let r = dx.hypot(dy).max(f64::MIN_POSITIVE);
        let u = [dx / r, dy / r];
        let t = [-u[1], u[0]];
        // Rows of the 2×4 Jacobian: [1, 0, u_x, t_x] and [0, 1, u_y, t_y].
        let rows = [[1.0, 0.0, u[0], t[0]], [0.0, 1.0, u[1], t[1]]];
        let vv = velocity[v as usize];
        for (row, val) in rows.iter().zip(vv) {
            for i in 0..4 {
                rhs[i] += row[i] * val;
                for j in 0..4 {
                    m[i][j] += row[i] * row[j];
                }
            }
        }
    }
    let a: Vec<f64> = m.iter().flatten().copied().collect();
    match solve_dense(4, &a, &rhs, 1) {
        Some(x) => [x[0], x[1], x[2], x[3]],
        None => [0.0; 4],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::disk_with_holes;
    use crate::geometry::face_areas;
    use crate::methods::circle_flow::Circle;
    use crate::qc::beltrami_coefficient;

    fn hole_boundary(m: &crate::TriMesh, holes: &[(f64, f64, f64)]) -> CircleBoundary {
        let topo = crate::mesh::topology::topology(m);
        let mut loops = topo.boundary_loops.clone();
        // The outer loop is the one farthest from the origin.
        loops.sort_by(|a, b| {
            let r = |l: &Vec<u32>| {
                let p = m.positions[l[0] as usize];
                -(p[0].hypot(p[1]))
            };
            r(a).total_cmp(&r(b))
        });
        let mut circles = vec![Circle {
            center: [0.0, 0.0],
            radius: 1.0,
        }];
        for l in &loops[1..] {
            let p = m.positions[l[0] as usize];
            let h = holes
                .iter()
                .min_by(|a, b| {
                    let d = |h: &&(f64, f64, f64)| ((p[0] - h.0).hypot(p[1] - h.1) - h.2).abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap();
            circles.push(Circle {
                center: [h.0, h.1],
                radius: h.2,
            });
        }
        CircleBoundary::new(m.n_vertices(), loops, circles)
    }

    #[test]
    fn fit_recovers_a_rigid_hole_motion() {
        let holes = [(0.3, 0.1, 0.2)];
        let m = disk_with_holes(&holes, 24).unwrap();
        let b = hole_boundary(&m, &holes);
        let c = b.circles[1].center;
        // v = Δc + p_r u + p_T t with Δc = (0.2, −0.1), p_r = 0.3, p_T = −0.5.
        let v: Vec<[f64; 2]> = m
            .positions
            .iter()
            .map(|p| {
                let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
                let r = dx.hypot(dy).max(1e-300);
                let (u, t) = ([dx / r, dy / r], [-dy / r, dx / r]);
                [
                    0.2 + 0.3 * u[0] - 0.5 * t[0],
                    -0.1 + 0.3 * u[1] - 0.5 * t[1],
                ]
            })
            .collect();
        let fit = fit_circle_motion(&m.positions, &v, &b.loops[1], c);
        for (a, e) in fit.iter().zip([0.2, -0.1, 0.3, -0.5]) {
            assert!((a - e).abs() < 1e-12, "{fit:?}");
        }
    }

    #[test]
    fn beltrami_gradients_match_finite_differences() {
        let holes = [(0.2, -0.1, 0.25)];
        let m = disk_with_holes(&holes, 20).unwrap();
        let b = hole_boundary(&m, &holes);
        let source = m.positions.clone();
        let areas = face_areas(&source, &m.faces);
        let weights = crate::fem::cotangent_weights(&source, &m.faces);
        let incidence = VertexFaces::new(m.n_vertices(), &m.faces);
        let terms = HoleTerms::new(
            &m.faces, &source, &areas, &weights, &incidence, &b, 1.0, 1.0,
        );
        // A map with a non-trivial ν: a shear of the interior, the hole moved off-centre.
        let moved = |q: [f64; 4]| -> Vec<[f64; 3]> {
            let (c0, r0) = (b.circles[1].center, b.circles[1].radius);
            m.positions
                .iter()
                .enumerate()
                .map(|(v, p)| {
                    if b.loop_of[v] == 1 {
                        let (dx, dy) = ((p[0] - c0[0]) / r0, (p[1] - c0[1]) / r0);
                        let (s, co) = q[3].sin_cos();
                        let r = r0 + q[2];
                        [
                            c0[0] + q[0] + r * (co * dx - s * dy),
                            c0[1] + q[1] + r * (s * dx + co * dy),
                            0.0,
                        ]
                    } else {
                        [p[0] + 0.2 * p[1] * p[1], p[1], 0.0]
                    }
                })
                .collect()
        };
        let energies = |q: [f64; 4]| -> (f64, f64) {
            let x = moved(q);
            let nu = beltrami_coefficient(&source, &x, &m.faces);
            let ring = &terms.ring[1];
            let e2: f64 = ring
                .iter()
                .map(|&f| areas[f as usize] * nu[f as usize].norm_sqr())
                .sum();
            let vnu: Vec<Complex64> = (0..m.n_vertices())
                .map(|v| {
                    let fs: Vec<usize> = (0..m.n_faces())
                        .filter(|&f| m.faces[f].contains(&(v as u32)))
                        .collect();
                    fs.iter().map(|&f| nu[f]).sum::<Complex64>() / fs.len().max(1) as f64
                })
                .collect();
            let e3: f64 = ring
                .iter()
                .map(|&f| {
                    let face = m.faces[f as usize];
                    (0..3)
                        .map(|c| {
                            let (a, bb) = (face[(c + 1) % 3] as usize, face[(c + 2) % 3] as usize);
                            weights[f as usize][c] * (vnu[a] - vnu[bb]).norm_sqr()
                        })
                        .sum::<f64>()
                })
                .sum();
            (e2, e3)
        };
        let q0 = [0.05, -0.03, 0.02, 0.1];
        let x0 = moved(q0);
        let nu0 = beltrami_coefficient(&source, &x0, &m.faces);
        let mut shifted = b.clone();
        shifted.circles[1].center = [
            b.circles[1].center[0] + q0[0],
            b.circles[1].center[1] + q0[1],
        ];
        shifted.circles[1].radius += q0[2];
        let (g2, g3) = terms.beltrami_gradients(1, &x0, &nu0, &shifted);
        let h = 1e-6;
        for j in 0..4 {
            let (mut qp, mut qm) = (q0, q0);
            qp[j] += h;
            qm[j] -= h;
            let (p2, p3) = energies(qp);
            let (m2, m3) = energies(qm);
            let (fd2, fd3) = ((p2 - m2) / (2.0 * h), (p3 - m3) / (2.0 * h));
            assert!(
                (fd2 - g2[j]).abs() < 1e-5 * (1.0 + fd2.abs()),
                "E2 q{j}: {fd2} vs {}",
                g2[j]
            );
            assert!(
                (fd3 - g3[j]).abs() < 1e-5 * (1.0 + fd3.abs()),
                "E3 q{j}: {fd3} vs {}",
                g3[j]
            );
        }
    }
}
