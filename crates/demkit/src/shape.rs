//! Prescribed target shapes for the shape-prescribed DEM (DEM paper, section 4.3, Algorithm 6;
//! the `--shape disk|square|rectangle:W:H|ellipse:A:B` option of the command line).
//!
//! A shape is a convex closed curve centred at the origin. Boundary vertices are placed on it by
//! arclength ([`Shape::boundary_positions`]: the initial map with an arclength-parameterized
//! boundary constraint, Algorithm 6 line 1) and pulled back onto it by nearest-point projection
//! after every iteration ([`Shape::project`], Algorithm 6 line 12).

use std::f64::consts::PI;

use crate::{Error, Result};

/// A target domain of the shape-prescribed DEM (DEM paper, Algorithm 6), bounded by a convex
/// closed curve centred at the origin.
///
/// Conventions: `Disk` is the unit disk; `Square` has side 2 (corners at (±1, ±1));
/// `Rectangle { width, height }` is `[−w/2, w/2] × [−h/2, h/2]`; `Ellipse { a, b }` has semi-axes
/// `a` along x and `b` along y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// The unit disk.
    Disk,
    /// The square `[−1, 1]²`.
    Square,
    /// The rectangle `[−width/2, width/2] × [−height/2, height/2]`.
    Rectangle {
        /// Side length along x.
        width: f64,
        /// Side length along y.
        height: f64,
    },
    /// The ellipse `(x/a)² + (y/b)² ≤ 1`.
    Ellipse {
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
    },
}

const VALID: &str = "valid shapes: disk, square, rectangle:W:H, ellipse:A:B (W, H, A, B > 0)";

/// The largest ratio of a rectangle's or an ellipse's two sides that is mapped onto.
pub const MAX_ASPECT: f64 = 1000.0;

impl Shape {
    /// Parses the prescribed boundary shape of Algorithm 6 from the command line's syntax
    /// (DESIGN, `--shape`): `disk`, `square`,
    /// `rectangle:W:H` or `ellipse:A:B`, with positive finite numbers; names are case-insensitive.
    /// Anything else is an [`Error::Argument`] naming the problem and the valid forms.
    pub fn parse(s: &str) -> Result<Shape> {
        let parts: Vec<&str> = s.trim().split(':').map(str::trim).collect();
        let name = parts[0].to_ascii_lowercase();
        let numbers = |what: [&str; 2]| -> Result<[f64; 2]> {
            if parts.len() != 3 {
                return Err(Error::Argument(format!(
                    "shape '{s}': expected {name}:{}:{} with two numbers; {VALID}",
                    what[0], what[1]
                )));
            }
            let mut out = [0.0; 2];
            for k in 0..2 {
                let v: f64 = parts[k + 1].parse().map_err(|_| {
                    Error::Argument(format!(
                        "shape '{s}': {} '{}' is not a number; {VALID}",
                        what[k],
                        parts[k + 1]
                    ))
                })?;
                if !(v.is_finite() && v > 0.0) {
                    return Err(Error::Argument(format!(
                        "shape '{s}': {} must be positive and finite, got {}; {VALID}",
                        what[k],
                        parts[k + 1]
                    )));
                }
                out[k] = v;
            }
            Ok(out)
        };
        let no_numbers = |shape: Shape| -> Result<Shape> {
            if parts.len() == 1 {
                Ok(shape)
            } else {
                Err(Error::Argument(format!(
                    "shape '{s}': '{name}' takes no parameters; {VALID}"
                )))
            }
        };
        // The two sides' ratio: beyond MAX_ASPECT the shape is a sliver no mesh of a usable
        // size fills with proper triangles.
        let aspect = |[p, q]: [f64; 2], what: &str| -> Result<[f64; 2]> {
            let ratio = p.max(q) / p.min(q);
            if ratio > MAX_ASPECT {
                return Err(Error::Argument(format!(
                    "shape '{s}': the ratio of {what} is {ratio:e}, more than {MAX_ASPECT} \
                     (the shape would be too thin to map onto)"
                )));
            }
            Ok([p, q])
        };
        match name.as_str() {
            "disk" => no_numbers(Shape::Disk),
            "square" => no_numbers(Shape::Square),
            "rectangle" => {
                let [width, height] = aspect(numbers(["W", "H"])?, "W and H")?;
                Ok(Shape::Rectangle { width, height })
            }
            "ellipse" => {
                let [a, b] = aspect(numbers(["A", "B"])?, "A and B")?;
                Ok(Shape::Ellipse { a, b })
            }
            _ => Err(Error::Argument(format!("unknown shape '{s}'; {VALID}"))),
        }
    }

    /// Half side lengths of a rectangle-like shape.
    fn half_sides(&self) -> Option<(f64, f64)> {
        match *self {
            Shape::Square => Some((1.0, 1.0)),
            Shape::Rectangle { width, height } => Some((width / 2.0, height / 2.0)),
            _ => None,
        }
    }

    /// Length of the boundary curve, for the arclength parameterization of Algorithm 6 line 1
    /// (for the ellipse, the complete elliptic integral computed by Gauss–Legendre quadrature,
    /// accurate to about 1e-14 relative).
    pub fn perimeter(&self) -> f64 {
        match *self {
            Shape::Disk => 2.0 * PI,
            Shape::Square | Shape::Rectangle { .. } => {
                let (hx, hy) = self.half_sides().unwrap_or((1.0, 1.0));
                4.0 * (hx + hy)
            }
            Shape::Ellipse { a, b } => EllipseArc::new(a, b).perimeter(),
        }
    }

    /// The point at arclength fraction `t` of the boundary, counter-clockwise from the positive
    /// x axis (`t` is taken modulo 1). For the ellipse this is the true arclength, not the angle
    /// parameter. This is the arclength-parameterized boundary of Algorithm 6, line 1.
    pub fn point_at(&self, t: f64) -> [f64; 2] {
        match *self {
            Shape::Ellipse { a, b } => EllipseArc::new(a, b).point_at(t),
            _ => self.point_at_simple(t),
        }
    }

    fn point_at_simple(&self, t: f64) -> [f64; 2] {
        let t = t.rem_euclid(1.0);
        match *self {
            Shape::Disk => {
                let th = 2.0 * PI * t;
                [th.cos(), th.sin()]
            }
            Shape::Ellipse { a, b } => EllipseArc::new(a, b).point_at(t),
            Shape::Square | Shape::Rectangle { .. } => {
                let (hx, hy) = self.half_sides().unwrap_or((1.0, 1.0));
                let mut s = t * 4.0 * (hx + hy);
                // Walk: up the right side from (hx, 0), left along the top, down the left side,
                // right along the bottom, up the right side back to (hx, 0).
                let legs: [([f64; 2], [f64; 2], f64); 5] = [
                    ([hx, 0.0], [0.0, 1.0], hy),
                    ([hx, hy], [-1.0, 0.0], 2.0 * hx),
                    ([-hx, hy], [0.0, -1.0], 2.0 * hy),
                    ([-hx, -hy], [1.0, 0.0], 2.0 * hx),
                    ([hx, -hy], [0.0, 1.0], hy),
                ];
                for (k, (start, dir, len)) in legs.iter().enumerate() {
                    if s < *len || k == legs.len() - 1 {
                        let s = s.min(*len);
                        return [start[0] + dir[0] * s, start[1] + dir[1] * s];
                    }
                    s -= len;
                }
                unreachable!("the last leg always returns")
            }
        }
    }

    /// Places the vertices of a boundary loop on the shape by arclength: given the 3D edge
    /// lengths of the loop (`loop_lengths[k]` from vertex `k` to `k + 1`, the last one closing
    /// the loop), vertex `k` goes to [`Shape::point_at`] of (Σ_{i<k} L_i)/(Σ L_i), so vertex 0 is
    /// on the positive x axis and the loop runs counter-clockwise. Zero or non-finite total
    /// length gives equal spacing. This is the arclength-parameterized boundary constraint of the
    /// initial map in Algorithm 6, line 1 (DEM paper, sections 4.3 and 5).
    pub fn boundary_positions(&self, loop_lengths: &[f64]) -> Vec<[f64; 2]> {
        let n = loop_lengths.len();
        let total: f64 = loop_lengths.iter().sum();
        let uniform = !(total > 0.0 && total.is_finite());
        let ellipse = match *self {
            Shape::Ellipse { a, b } => Some(EllipseArc::new(a, b)),
            _ => None,
        };
        let mut out = Vec::with_capacity(n);
        let mut s = 0.0;
        for (k, len) in loop_lengths.iter().enumerate() {
            let t = if uniform {
                k as f64 / n as f64
            } else {
                s / total
            };
            out.push(match &ellipse {
                Some(e) => e.point_at(t),
                None => self.point_at_simple(t),
            });
            s += len;
        }
        out
    }

    /// The nearest point of the boundary curve to `p` (for points inside and outside).
    /// Disk: `p/|p|` (the origin goes to (1, 0)). Rectangle and square: the nearest point of the
    /// four sides. Ellipse: the true nearest point, by a bisection on the Lagrange multiplier
    /// (Eberly, "Distance from a point to an ellipse"), accurate to about 1e-15 relative.
    /// Points on the curve are fixed points, so the projection is idempotent. This is the
    /// projection of the boundary vertices onto the prescribed shape, Algorithm 6, line 12.
    pub fn project(&self, p: [f64; 2]) -> [f64; 2] {
        match *self {
            Shape::Disk => {
                let r = p[0].hypot(p[1]);
                if r > 0.0 && r.is_finite() {
                    [p[0] / r, p[1] / r]
                } else {
                    [1.0, 0.0]
                }
            }
            Shape::Square | Shape::Rectangle { .. } => {
                let (hx, hy) = self.half_sides().unwrap_or((1.0, 1.0));
                project_rectangle(hx, hy, p)
            }
            Shape::Ellipse { a, b } => project_ellipse(a, b, p),
        }
    }
}

/// Nearest point of the boundary of `[−hx, hx] × [−hy, hy]`.
fn project_rectangle(hx: f64, hy: f64, p: [f64; 2]) -> [f64; 2] {
    let [x, y] = p;
    if x.abs() >= hx || y.abs() >= hy {
        // On or outside the boundary: clamping gives the nearest point, which is on a side.
        return [x.clamp(-hx, hx), y.clamp(-hy, hy)];
    }
    // Strictly inside: move to the nearest side.
    let candidates = [
        (hx - x, [hx, y]),
        (hy - y, [x, hy]),
        (x + hx, [-hx, y]),
        (y + hy, [x, -hy]),
    ];
    let mut best = candidates[0];
    for c in &candidates[1..] {
        if c.0 < best.0 {
            best = *c;
        }
    }
    best.1
}

/// Nearest point of the ellipse `(x/a)² + (y/b)² = 1` to `p`.
fn project_ellipse(a: f64, b: f64, p: [f64; 2]) -> [f64; 2] {
    // Reduce to the first quadrant with e0 >= e1.
    let (sx, sy) = (p[0].is_sign_negative(), p[1].is_sign_negative());
    let (ax, ay) = (p[0].abs(), p[1].abs());
    let [qx, qy] = if a >= b {
        ellipse_nearest_first_quadrant(a, b, ax, ay)
    } else {
        let [u, v] = ellipse_nearest_first_quadrant(b, a, ay, ax);
        [v, u]
    };
    [if sx { -qx } else { qx }, if sy { -qy } else { qy }]
}

/// Eberly's robust nearest point on the ellipse with semi-axes `e0 >= e1 > 0` to `(y0, y1)`,
/// `y0, y1 >= 0`.
fn ellipse_nearest_first_quadrant(e0: f64, e1: f64, y0: f64, y1: f64) -> [f64; 2] {
    if y1 > 0.0 {
        if y0 > 0.0 {
            let z0 = y0 / e0;
            let z1 = y1 / e1;
            let g = z0 * z0 + z1 * z1 - 1.0;
            if g == 0.0 {
                return [y0, y1];
            }
            let r0 = (e0 / e1) * (e0 / e1);
            let s = ellipse_root(r0, z0, z1, g);
            [r0 * y0 / (s + r0), y1 / (s + 1.0)]
        } else {
            [0.0, e1]
        }
    } else {
        let numer0 = e0 * y0;
        let denom0 = e0 * e0 - e1 * e1;
        if numer0 < denom0 {
            let xde0 = numer0 / denom0;
            [e0 * xde0, e1 * (1.0 - xde0 * xde0).max(0.0).sqrt()]
        } else {
            [e0, 0.0]
        }
    }
}

/// Root of `(r0 z0/(s + r0))² + (z1/(s + 1))² − 1` by bisection down to adjacent floats.
fn ellipse_root(r0: f64, z0: f64, z1: f64, g: f64) -> f64 {
    let n0 = r0 * z0;
    let mut s0 = z1 - 1.0;
    let mut s1 = if g < 0.0 { 0.0 } else { n0.hypot(z1) - 1.0 };
    let mut s = 0.0;
    for _ in 0..2200 {
        s = 0.5 * (s0 + s1);
        if s == s0 || s == s1 {
            break;
        }
        let ratio0 = n0 / (s + r0);
        let ratio1 = z1 / (s + 1.0);
        let g = ratio0 * ratio0 + ratio1 * ratio1 - 1.0;
        if g > 0.0 {
            s0 = s;
        } else if g < 0.0 {
            s1 = s;
        } else {
            break;
        }
    }
    s
}

/// Arclength of the ellipse `(a cos τ, b sin τ)` as a function of the angle parameter τ:
/// a table at uniform τ plus Gauss–Legendre quadrature and a safeguarded Newton inversion.
struct EllipseArc {
    a: f64,
    b: f64,
    /// `cumulative[k]` = arclength from τ = 0 to τ = 2πk/N.
    cumulative: Vec<f64>,
}

const ELLIPSE_TABLE: usize = 512;

/// 10-point Gauss–Legendre nodes and weights on [−1, 1].
const GL_NODES: [f64; 5] = [
    0.148_874_338_981_631_2,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL_WEIGHTS: [f64; 5] = [
    0.295_524_224_714_752_9,
    0.269_266_719_309_996_4,
    0.219_086_362_515_982,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_1,
];

impl EllipseArc {
    fn new(a: f64, b: f64) -> Self {
        let mut e = EllipseArc {
            a,
            b,
            cumulative: Vec::with_capacity(ELLIPSE_TABLE + 1),
        };
        let h = 2.0 * PI / ELLIPSE_TABLE as f64;
        let mut s = 0.0;
        e.cumulative.push(0.0);
        for k in 0..ELLIPSE_TABLE {
            s += e.integrate(k as f64 * h, (k + 1) as f64 * h);
            e.cumulative.push(s);
        }
        e
    }

    fn speed(&self, tau: f64) -> f64 {
        (self.a * tau.sin()).hypot(self.b * tau.cos())
    }

    fn integrate(&self, t0: f64, t1: f64) -> f64 {
        let (m, r) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
        let mut s = 0.0;
        for (x, w) in GL_NODES.iter().zip(GL_WEIGHTS.iter()) {
            s += w * (self.speed(m - r * x) + self.speed(m + r * x));
        }
        s * r
    }

    fn perimeter(&self) -> f64 {
        self.cumulative[ELLIPSE_TABLE]
    }

    /// The point at arclength fraction `t` (mod 1), counter-clockwise from (a, 0).
    fn point_at(&self, t: f64) -> [f64; 2] {
        let t = t.rem_euclid(1.0);
        let target = t * self.perimeter();
        let h = 2.0 * PI / ELLIPSE_TABLE as f64;
        // Interval k with cumulative[k] <= target < cumulative[k + 1].
        let k = self
            .cumulative
            .partition_point(|&c| c <= target)
            .saturating_sub(1)
            .min(ELLIPSE_TABLE - 1);
        let (mut lo, mut hi) = (k as f64 * h, (k + 1) as f64 * h);
        let base = self.cumulative[k];
        // Safeguarded Newton on F(τ) = base + ∫_{lo}^{τ} speed − target, monotone increasing.
        let t_lo = lo;
        let mut tau =
            lo + h * (target - base) / (self.cumulative[k + 1] - base).max(f64::MIN_POSITIVE);
        for _ in 0..60 {
            tau = tau.clamp(lo, hi);
            let f = base + self.integrate(t_lo, tau) - target;
            if f > 0.0 {
                hi = tau;
            } else {
                lo = tau;
            }
            let step = f / self.speed(tau).max(f64::MIN_POSITIVE);
            let next = tau - step;
            let next = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
            if (next - tau).abs() <= 1e-16 * (1.0 + tau.abs()) {
                tau = next;
                break;
            }
            tau = next;
        }
        [self.a * tau.cos(), self.b * tau.sin()]
    }
}

#[cfg(test)]
mod tests;
