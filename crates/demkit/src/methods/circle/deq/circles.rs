//! The boundary of a circle domain in motion: the outer loop slides on the unit circle, each
//! hole's loop stays on a circle that moves, grows and shrinks, its vertices sliding along it
//! (the domain alteration of GM, DEQ paper (5.10)–(5.17), with every vertex's own slide kept).

use super::beltrami::Relaxation;
pub(crate) use super::circle::Circle;
use super::patch::Patch;
use crate::fem::{DirichletSystem, cotangent_weights};
use crate::methods::disk::planar_diffusion::{Constraint, linear_move};

/// The motion of one hole fitted to the displacement of its loop vertices: a translation
/// `dc`, a change of radius `dr` (least squares on the normal components, (5.14)–(5.15)), and
/// every vertex's slide along the circle (5.16), per vertex.
fn fit_motion(c: &Circle, x: &[[f64; 3]], lp: &[u32], step: &[[f64; 2]]) -> ([f64; 2], f64) {
    // Normal equations of Σ_j (dc·u_j + dr − s_j·u_j)² in (dcx, dcy, dr).
    let mut a = [0.0f64; 9];
    let mut b = [0.0f64; 3];
    for &v in lp {
        let u = c.radial(x[v as usize]);
        let s = step[v as usize];
        let g = [u[0], u[1], 1.0];
        let rhs = s[0] * u[0] + s[1] * u[1];
        for i in 0..3 {
            for j in 0..3 {
                a[3 * i + j] += g[i] * g[j];
            }
            b[i] += g[i] * rhs;
        }
    }
    match crate::linalg::solve_dense(3, &a, &b, 1) {
        Some(s) => ([s[0], s[1]], s[2]),
        None => ([0.0, 0.0], 0.0),
    }
}

/// The circle domain's boundary as a constraint of the planar diffusion: outer-loop vertices
/// slide on the unit circle, hole loops move as circles (or keep them, `fixed_holes`). The
/// correction this makes to the free displacement of the loops is carried into the region by its harmonic extension (cotangent weights of the
/// current map, which move a locally affine correction affinely), so the triangles next to a
/// loop move with it instead of being crushed against it. After every move the hole fillings
/// are laid out again and the map is relaxed towards conformality ([`Relaxation`]).
pub(crate) struct CircleBoundary<'a> {
    pub outer: &'a [u32],
    pub holes: &'a [Vec<u32>],
    pub fixed_holes: bool,
    pub patches: &'a [Patch],
    /// The region's faces (they come first in the diffusion's faces; only they limit a step,
    /// the fillings are rebuilt, not moved).
    pub region_faces: &'a [[u32; 3]],
    /// The region's Laplacian with every loop vertex fixed.
    pub extension: DirichletSystem,
    pub relaxation: Relaxation,
}

impl Constraint for CircleBoundary<'_> {
    fn admissible_step(&self, r: &[[f64; 3]], step: &mut [[f64; 2]]) {
        let free = step.to_vec();
        for &v in self.outer {
            let u = UNIT.radial(r[v as usize]);
            let s = &mut step[v as usize];
            let slide = -s[0] * u[1] + s[1] * u[0];
            *s = [-slide * u[1], slide * u[0]];
        }
        for lp in self.holes {
            let c = Circle::fit(r, lp);
            let (dc, dr) = self.motion(&c, r, lp, step);
            for &v in lp {
                let u = c.radial(r[v as usize]);
                let s = &mut step[v as usize];
                let slide = -(s[0] - dc[0]) * u[1] + (s[1] - dc[1]) * u[0];
                *s = [
                    dc[0] + dr * u[0] - slide * u[1],
                    dc[1] + dr * u[1] + slide * u[0],
                ];
            }
        }
        let mut correction = vec![[0.0; 3]; r.len()];
        for &v in self.outer.iter().chain(self.holes.iter().flatten()) {
            let (a, b) = (step[v as usize], free[v as usize]);
            correction[v as usize] = [a[0] - b[0], a[1] - b[1], 0.0];
        }
        let weights = cotangent_weights(r, self.region_faces);
        if let Ok(d) = self.extension.solve(&weights, &correction) {
            for (v, s) in step.iter_mut().enumerate() {
                if !self.extension.is_fixed(v) {
                    s[0] += d[v][0];
                    s[1] += d[v][1];
                }
            }
        }
        for p in self.patches {
            p.clear_interior(step);
        }
    }

    fn realize(&self, r: &[[f64; 3]], step: &[[f64; 2]], tau: f64) -> Vec<[f64; 3]> {
        let mut out = linear_move(r, step, tau);
        for &v in self.outer {
            out[v as usize] = rotate_on(&UNIT, &UNIT, r[v as usize], step[v as usize], tau);
        }
        for lp in self.holes {
            let c = Circle::fit(r, lp);
            let (dc, dr) = self.motion(&c, r, lp, step);
            let moved = Circle {
                center: [c.center[0] + tau * dc[0], c.center[1] + tau * dc[1]],
                radius: c.radius + tau * dr,
            };
            for &v in lp {
                let s = step[v as usize];
                let rel = [s[0] - dc[0], s[1] - dc[1]];
                out[v as usize] = rotate_on(&c, &moved, r[v as usize], rel, tau);
            }
        }
        for p in self.patches {
            p.place(&mut out);
        }
        out
    }

    fn limits_step(&self, face: usize) -> bool {
        face < self.region_faces.len()
    }

    fn regularize(&self, r: &mut [[f64; 3]], time: f64) {
        self.relaxation.apply(r, time);
    }
}

impl CircleBoundary<'_> {
    /// The hole's motion fitted to `step` (none when the holes keep their circles).
    fn motion(&self, c: &Circle, r: &[[f64; 3]], lp: &[u32], step: &[[f64; 2]]) -> ([f64; 2], f64) {
        if self.fixed_holes {
            ([0.0, 0.0], 0.0)
        } else {
            fit_motion(c, r, lp, step)
        }
    }
}

/// The unit circle.
const UNIT: Circle = Circle {
    center: [0.0, 0.0],
    radius: 1.0,
};

/// The point of circle `to` at the angle of `p` on circle `from`, turned by the tangential
/// part of `tau · s` (as an arc length on `from`).
fn rotate_on(from: &Circle, to: &Circle, p: [f64; 3], s: [f64; 2], tau: f64) -> [f64; 3] {
    let u = from.radial(p);
    let slide = -s[0] * u[1] + s[1] * u[0];
    let (sin, cos) = (tau * slide / from.radius).sin_cos();
    let w = [cos * u[0] - sin * u[1], sin * u[0] + cos * u[1]];
    [
        to.center[0] + to.radius * w[0],
        to.center[1] + to.radius * w[1],
        0.0,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_is_fitted_exactly_and_projects_radially() {
        let c = Circle {
            center: [0.3, -0.2],
            radius: 0.25,
        };
        let x: Vec<[f64; 3]> = (0..7)
            .map(|k| {
                let t = 0.9 * k as f64;
                [
                    c.center[0] + c.radius * t.cos(),
                    c.center[1] + c.radius * t.sin(),
                    0.0,
                ]
            })
            .collect();
        let lp: Vec<u32> = (0..7).collect();
        let f = Circle::fit(&x, &lp);
        assert!((f.center[0] - 0.3).abs() < 1e-12 && (f.center[1] + 0.2).abs() < 1e-12);
        assert!((f.radius - 0.25).abs() < 1e-12);
        let p = c.project([1.3, -0.2, 0.4]);
        assert!((p[0] - 0.55).abs() < 1e-15 && (p[1] + 0.2).abs() < 1e-15 && p[2] == 0.0);
    }

    #[test]
    fn a_translating_growing_hole_is_fitted_from_its_vertices_moves() {
        // Every vertex moves by dc + dr u plus its own slide: the fit recovers dc and dr.
        let c = Circle {
            center: [0.0, 0.0],
            radius: 0.5,
        };
        let n = 12;
        let x: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                [0.5 * t.cos(), 0.5 * t.sin(), 0.0]
            })
            .collect();
        let lp: Vec<u32> = (0..n as u32).collect();
        let step: Vec<[f64; 2]> = x
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let u = [p[0] / 0.5, p[1] / 0.5];
                let slide = 0.01 * (k as f64).sin();
                [
                    0.02 + 0.05 * u[0] - slide * u[1],
                    -0.01 + 0.05 * u[1] + slide * u[0],
                ]
            })
            .collect();
        let (dc, dr) = fit_motion(&c, &x, &lp, &step);
        assert!((dc[0] - 0.02).abs() < 1e-12 && (dc[1] + 0.01).abs() < 1e-12);
        assert!((dr - 0.05).abs() < 1e-12);
    }

    #[test]
    fn rotating_on_a_circle_stays_on_it() {
        let from = Circle {
            center: [0.1, 0.0],
            radius: 0.3,
        };
        let to = Circle {
            center: [0.15, 0.02],
            radius: 0.35,
        };
        let q = rotate_on(&from, &to, [0.4, 0.0, 0.0], [0.0, 0.03], 0.5);
        assert!(((q[0] - 0.15).hypot(q[1] - 0.02) - 0.35).abs() < 1e-15);
        // A slide of 0.015 along a radius-0.3 circle turns by 0.05 rad.
        assert!(((q[1] - 0.02).atan2(q[0] - 0.15) - 0.05).abs() < 1e-12);
    }
}
