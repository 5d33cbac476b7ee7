//! A z-buffered triangle rasterizer into an RGB sample buffer, resolved (box-filtered) into a
//! picture; supersampling gives smooth edges without an anti-aliasing pass per triangle.

use tiny_skia::{IntSize, Pixmap};

/// An RGB colour.
pub type Rgb = [u8; 3];

/// A two-tone pattern over a triangle: a point for each corner; samples whose point,
/// interpolated linearly between those, `is_dark` take the colour `dark`.
#[derive(Clone, Copy)]
pub struct Shading<'a> {
    /// A point for each corner.
    pub corners: &'a [[f64; 3]; 3],
    /// Whether a point takes the dark colour.
    pub is_dark: &'a dyn Fn([f64; 3]) -> bool,
    /// The dark colour.
    pub dark: Rgb,
}

/// Thin lines along a triangle's edges: half their width in samples, and their colour.
#[derive(Debug, Clone, Copy)]
pub struct EdgeLines {
    /// Samples within this distance of an edge take the line colour.
    pub half_width: f64,
    /// The line colour.
    pub color: Rgb,
}

/// A grid of samples, each with a colour and a depth (larger is nearer the viewer).
pub struct Canvas {
    width: usize,
    height: usize,
    color: Vec<Rgb>,
    depth: Vec<f32>,
}

impl Canvas {
    /// A `width` × `height` grid of samples filled with `background`, infinitely far away.
    pub fn new(width: usize, height: usize, background: Rgb) -> Canvas {
        Canvas {
            width,
            height,
            color: vec![background; width * height],
            depth: vec![f32::NEG_INFINITY; width * height],
        }
    }

    /// The colour of sample (x, y), row 0 at the top.
    #[cfg(test)]
    pub fn sample(&self, x: usize, y: usize) -> Rgb {
        self.color[y * self.width + x]
    }

    /// Fills a triangle given in sample coordinates (x right, y down, z depth, larger nearer).
    ///
    /// Corners are snapped to 1/256 of a sample and the coverage is decided in exact integer
    /// arithmetic: a sample is covered when its centre (x + ½, y + ½) lies inside the triangle;
    /// a centre on an edge belongs to the triangle for which that edge is a "top-left" edge, so
    /// two triangles sharing an edge never both cover a sample on it and never both miss it.
    /// Depth is interpolated linearly; the sample keeps the nearest face. Degenerate or
    /// non-finite triangles draw nothing.
    pub fn fill_triangle(&mut self, p: [[f64; 3]; 3], color: Rgb, edges: Option<EdgeLines>) {
        self.fill_triangle_shaded(p, color, edges, None);
    }

    /// [`fill_triangle`](Self::fill_triangle) with a two-tone pattern carried by the mesh
    /// (such as a checkerboard in parameter coordinates), when given.
    pub fn fill_triangle_shaded(
        &mut self,
        p: [[f64; 3]; 3],
        color: Rgb,
        edges: Option<EdgeLines>,
        shade: Option<Shading>,
    ) {
        if p.iter().flatten().any(|c| !c.is_finite()) {
            return;
        }
        let mut attr = shade.map(|sh| *sh.corners);
        let snap = |v: f64| (v * SUB as f64).round().clamp(-LIMIT, LIMIT) as i64;
        let mut q = p.map(|c| [snap(c[0]), snap(c[1])]);
        let mut z = p.map(|c| c[2]);
        let mut area = cross_i(q[0], q[1], q[2]);
        if area == 0 {
            return;
        }
        if area < 0 {
            q.swap(1, 2);
            z.swap(1, 2);
            if let Some(a) = attr.as_mut() {
                a.swap(1, 2);
            }
            area = -area;
        }
        // Sample rows and columns whose centres can be inside.
        let lo = |k: usize| q.iter().map(|c| c[k]).min().unwrap_or(0);
        let hi = |k: usize| q.iter().map(|c| c[k]).max().unwrap_or(0);
        let first = |v: i64| ((v - SUB / 2).div_euclid(SUB)).max(0);
        let x0 = first(lo(0)) as usize;
        let y0 = first(lo(1)) as usize;
        let x1 = (((hi(0) - SUB / 2).div_euclid(SUB) + 1).max(0) as usize).min(self.width);
        let y1 = (((hi(1) - SUB / 2).div_euclid(SUB) + 1).max(0) as usize).min(self.height);
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        // Edge k runs between the corners other than k; E_k(s) = A_k (s_y − u_y) − B_k (s_x − u_x)
        // is positive inside. A top-left edge also takes E_k = 0 (bias 1, then test > 0).
        let ends = [(q[1], q[2]), (q[2], q[0]), (q[0], q[1])];
        let mut step_x = [0i64; 3];
        let mut row = [0i64; 3];
        let mut limit = [f64::NEG_INFINITY; 3];
        let (cx, cy) = (x0 as i64 * SUB + SUB / 2, y0 as i64 * SUB + SUB / 2);
        for (k, (u, v)) in ends.iter().enumerate() {
            let (a, b) = (v[0] - u[0], v[1] - u[1]);
            let top_left = b < 0 || (b == 0 && a > 0);
            row[k] = a * (cy - u[1]) - b * (cx - u[0]) + i64::from(top_left);
            step_x[k] = -b * SUB;
            if let Some(e) = edges {
                // E_k / (edge length) is the distance in 1/256 samples.
                limit[k] = e.half_width * (a as f64).hypot(b as f64) * SUB as f64;
            }
        }
        let step_y = ends.map(|(u, v)| (v[0] - u[0]) * SUB);
        let inv = 1.0 / area as f64;
        for y in y0..y1 {
            let mut w = row;
            let base = y * self.width;
            for x in x0..x1 {
                if w[0] > 0 && w[1] > 0 && w[2] > 0 {
                    let d = ((w[0] as f64 * z[0] + w[1] as f64 * z[1] + w[2] as f64 * z[2]) * inv)
                        as f32;
                    let i = base + x;
                    if d > self.depth[i] {
                        self.depth[i] = d;
                        let on_edge = (0..3).any(|k| (w[k] as f64) < limit[k]);
                        self.color[i] = match (edges, shade, &attr) {
                            (Some(e), _, _) if on_edge => e.color,
                            (_, Some(sh), Some(a)) => {
                                let t = w.map(|v| v as f64 * inv);
                                let at = std::array::from_fn(|k| {
                                    t[0] * a[0][k] + t[1] * a[1][k] + t[2] * a[2][k]
                                });
                                if (sh.is_dark)(at) { sh.dark } else { color }
                            }
                            _ => color,
                        };
                    }
                }
                for k in 0..3 {
                    w[k] += step_x[k];
                }
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
        }
    }

    /// The picture: each pixel the mean of a `factor` × `factor` block of samples, opaque.
    /// The canvas size must be a multiple of `factor`.
    pub fn resolve(&self, factor: usize) -> Option<Pixmap> {
        let factor = factor.max(1);
        let (w, h) = (self.width / factor, self.height / factor);
        let mut data = Vec::with_capacity(w * h * 4);
        let n = (factor * factor) as u32;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 3];
                for sy in 0..factor {
                    let row = (y * factor + sy) * self.width + x * factor;
                    for s in &self.color[row..row + factor] {
                        for k in 0..3 {
                            sum[k] += u32::from(s[k]);
                        }
                    }
                }
                data.extend(sum.map(|v| ((v + n / 2) / n) as u8));
                data.push(255);
            }
        }
        Pixmap::from_vec(data, IntSize::from_wh(w as u32, h as u32)?)
    }
}

/// Sub-sample steps per sample of the snapped corners.
const SUB: i64 = 256;

/// Snapped coordinates are kept within ±2^30 (products stay far from overflow).
const LIMIT: f64 = (1u64 << 30) as f64;

/// (b − a) × (c − a) in the xy-plane: twice the signed area of the triangle a, b, c.
fn cross_i(a: [i64; 2], b: [i64; 2], c: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    const BG: Rgb = [255, 255, 255];
    const RED: Rgb = [255, 0, 0];
    const BLUE: Rgb = [0, 0, 255];

    fn covered(c: &Canvas, color: Rgb) -> Vec<(usize, usize)> {
        let mut v = Vec::new();
        for y in 0..c.height {
            for x in 0..c.width {
                if c.sample(x, y) == color {
                    v.push((x, y));
                }
            }
        }
        v
    }

    #[test]
    fn a_right_triangle_covers_exactly_the_centres_inside_it() {
        // Legs along x and y from (0.2, 0.2), length 8: the centre (x+½, y+½) is inside when
        // x + y + 1 < 8.4, i.e. x + y ≤ 7: 8 + 7 + ... + 1 = 36 samples.
        let mut c = Canvas::new(12, 12, BG);
        c.fill_triangle(
            [[0.2, 0.2, 0.0], [8.2, 0.2, 0.0], [0.2, 8.2, 0.0]],
            RED,
            None,
        );
        let got = covered(&c, RED);
        let want: Vec<(usize, usize)> = (0..12)
            .flat_map(|y| (0..12).map(move |x| (x, y)))
            .filter(|&(x, y)| x + y <= 7)
            .collect();
        assert_eq!(got, want);
        // Winding does not matter.
        let mut d = Canvas::new(12, 12, BG);
        d.fill_triangle(
            [[0.2, 0.2, 0.0], [0.2, 8.2, 0.0], [8.2, 0.2, 0.0]],
            RED,
            None,
        );
        assert_eq!(covered(&d, RED), want);
    }

    #[test]
    fn two_triangles_sharing_an_edge_cover_every_sample_once() {
        // A 6 × 6 square split along its diagonal, which passes through sample centres.
        let mut c = Canvas::new(6, 6, BG);
        let (p, q, r, s) = (
            [0.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 6.0, 0.0],
            [0.0, 6.0, 0.0],
        );
        c.fill_triangle([p, q, r], RED, None);
        let red = covered(&c, RED).len();
        c.fill_triangle([p, r, s], BLUE, None);
        let blue = covered(&c, BLUE).len();
        assert_eq!(red + blue, 36);
        assert_eq!(covered(&c, BG).len(), 0);
        assert_eq!(
            covered(&c, RED).len(),
            red,
            "equal depth: the first face stays"
        );
        // The 6 centres on the diagonal go to one side: 15 + 6 and 15.
        assert!(
            red == 21 && blue == 15 || red == 15 && blue == 21,
            "{red} {blue}"
        );
    }

    #[test]
    fn the_depth_test_keeps_the_nearer_face_whatever_the_order() {
        // Two parallel faces covering the whole canvas.
        let far = [[-1.0, -1.0, -1.0], [20.0, -1.0, -1.0], [-1.0, 20.0, -1.0]];
        let near = [[-1.0, -1.0, 1.0], [20.0, -1.0, 1.0], [-1.0, 20.0, 1.0]];
        for order in [[far, near], [near, far]] {
            let mut c = Canvas::new(8, 8, BG);
            c.fill_triangle(order[0], if order[0] == far { BLUE } else { RED }, None);
            c.fill_triangle(order[1], if order[1] == far { BLUE } else { RED }, None);
            assert_eq!(covered(&c, BLUE).len(), 0);
            assert_eq!(covered(&c, RED).len(), 64);
        }
        // Crossing faces: depth is interpolated, z = z0 + (z1 − z0)(x + 8)/64, equal for
        // both at x = 24; each face wins where it is nearer.
        let tilted = |z0: f64, z1: f64| [[-8.0, -8.0, z0], [56.0, -8.0, z1], [-8.0, 56.0, z0]];
        let mut d = Canvas::new(32, 8, BG);
        d.fill_triangle(tilted(-1.0, 1.0), RED, None);
        d.fill_triangle(tilted(1.0, -1.0), BLUE, None);
        assert_eq!(d.sample(4, 3), BLUE);
        assert_eq!(d.sample(23, 3), BLUE);
        assert_eq!(d.sample(24, 3), RED);
        assert_eq!(d.sample(30, 7), RED);
    }

    #[test]
    fn edge_lines_and_degenerate_triangles() {
        let mut c = Canvas::new(16, 16, BG);
        let e = EdgeLines {
            half_width: 1.0,
            color: BLUE,
        };
        c.fill_triangle(
            [[0.0, 0.0, 0.0], [16.0, 0.0, 0.0], [0.0, 16.0, 0.0]],
            RED,
            Some(e),
        );
        assert_eq!(c.sample(0, 5), BLUE, "next to the left edge");
        assert_eq!(c.sample(5, 0), BLUE, "next to the top edge");
        assert_eq!(c.sample(4, 4), RED, "inside");
        let mut d = Canvas::new(4, 4, BG);
        d.fill_triangle(
            [[0.0, 0.0, 0.0], [2.0, 2.0, 0.0], [4.0, 4.0, 0.0]],
            RED,
            None,
        );
        d.fill_triangle(
            [[0.0, 0.0, 0.0], [f64::NAN, 2.0, 0.0], [4.0, 0.0, 0.0]],
            RED,
            None,
        );
        assert_eq!(covered(&d, RED).len(), 0);
    }

    #[test]
    fn shading_follows_the_corner_points_whatever_the_winding() {
        // The corner points are the corners themselves: samples left of x = 4 keep the
        // colour, the others are dark.
        let tri = [[0.0, 0.0, 0.0], [8.0, 0.0, 0.0], [0.0, 8.0, 0.0]];
        let right = |p: [f64; 3]| p[0] >= 4.0;
        for corners in [tri, [tri[0], tri[2], tri[1]]] {
            let mut c = Canvas::new(8, 8, BG);
            let sh = Shading {
                corners: &corners,
                is_dark: &right,
                dark: [100, 50, 0],
            };
            c.fill_triangle_shaded(corners, [200, 100, 0], None, Some(sh));
            assert_eq!(c.sample(1, 1), [200, 100, 0]);
            assert_eq!(c.sample(3, 3), [200, 100, 0]);
            assert_eq!(c.sample(5, 1), [100, 50, 0]);
            assert_eq!(c.sample(7, 7), BG);
        }
    }

    #[test]
    fn resolve_averages_blocks() {
        let mut c = Canvas::new(4, 2, BG);
        // Cover the left 2 × 2 block only: its pixel is red, the right one stays white.
        c.fill_triangle(
            [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0]],
            RED,
            None,
        );
        c.fill_triangle(
            [[0.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]],
            RED,
            None,
        );
        let p = c.resolve(2).unwrap();
        assert_eq!((p.width(), p.height()), (2, 1));
        assert_eq!(&p.data()[..8], &[255, 0, 0, 255, 255, 255, 255, 255]);
    }
}
