//! A mesh drawn with one colour per face: flat from above for planar meshes, lit by a light
//! from the upper left for surfaces in space; thin darker edges when faces are large enough
//! on the picture to show them, or else a checkerboard carried by the mesh.

use super::camera::{Camera, View};
use super::checker::{Checker, DARK};
use super::colormap::shade;
use super::raster::{Canvas, EdgeLines, Rgb, Shading};
use tiny_skia::Pixmap;

/// The picture's background.
pub const BACKGROUND: Rgb = [255, 255, 255];

/// How to draw a mesh.
#[derive(Debug, Clone, Copy)]
pub struct Style {
    /// The direction of view.
    pub view: View,
    /// Light the faces (surfaces in space); otherwise each face has exactly its colour.
    pub lit: bool,
    /// The picture's width in pixels.
    pub width: usize,
    /// The picture's height in pixels.
    pub height: usize,
}

impl Style {
    /// A `size` × `size` picture.
    pub fn square(view: View, lit: bool, size: usize) -> Style {
        Style {
            view,
            lit,
            width: size,
            height: size,
        }
    }
}

/// A checkerboard carried by the mesh: `checker`'s cells of the point `points[v]` given to
/// every vertex v (the initial map), interpolated across each face.
#[derive(Clone, Copy)]
pub struct Pattern<'a> {
    /// One point per vertex.
    pub points: &'a [[f64; 3]],
    /// The cells.
    pub checker: Checker,
}

/// Samples per pixel along each axis (the supersampling that smooths edges).
fn supersampling(size: usize) -> usize {
    if size <= 2048 { 2 } else { 1 }
}

/// Faces whose mean projected edge is at least this many pixels get edge lines.
const EDGE_MIN_PIXELS: f64 = 10.0;

/// Draws the faces of `positions` with `colors` (one per face) in `style`, with `pattern`
/// when given.
pub fn draw(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    colors: &[Rgb],
    style: Style,
    pattern: Option<Pattern>,
) -> Option<Pixmap> {
    let ss = supersampling(style.width.max(style.height));
    let (w, h) = (style.width * ss, style.height * ss);
    let camera = Camera::fit(positions, style.view, w as f64, h as f64, 0.04);
    let projected: Vec<[f64; 3]> = positions.iter().map(|&p| camera.project(p)).collect();
    let mut canvas = Canvas::new(w, h, BACKGROUND);
    // A checkerboard shows the faces' distortion itself: no edge lines over it.
    let edges = pattern.is_none() && show_edges(&projected, faces, ss as f64);
    // The light, in screen axes (right, up, toward the viewer): from the upper left, in front.
    let light = normalized([-0.35, 0.45, 0.82]);
    for (f, &color) in faces.iter().zip(colors) {
        let p = f.map(|v| projected[v as usize]);
        let color = if style.lit {
            let c = f.map(|v| positions[v as usize]);
            let n = camera.screen_direction(normalized(cross(sub(c[1], c[0]), sub(c[2], c[0]))));
            // Two-sided: a face seen from behind is lit like its front.
            let diffuse = (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]).abs();
            let k = 0.32 + 0.68 * if diffuse.is_finite() { diffuse } else { 0.0 };
            shade(color, k)
        } else {
            color
        };
        let lines = edges.then_some(EdgeLines {
            half_width: 0.45 * ss as f64,
            color: shade(color, 0.7),
        });
        match pattern {
            Some(pt) => {
                let corners = f.map(|v| pt.points[v as usize]);
                let is_dark = |q: [f64; 3]| pt.checker.is_dark(q);
                let sh = Shading {
                    corners: &corners,
                    is_dark: &is_dark,
                    dark: shade(color, DARK),
                };
                canvas.fill_triangle_shaded(p, color, lines, Some(sh));
            }
            None => canvas.fill_triangle(p, color, lines),
        }
    }
    canvas.resolve(ss)
}

/// Edge lines are worth drawing when the mean projected edge is long enough on the picture.
fn show_edges(projected: &[[f64; 3]], faces: &[[u32; 3]], ss: f64) -> bool {
    if faces.is_empty() {
        return false;
    }
    let total: f64 = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| projected[v as usize]);
            let d = |u: [f64; 3], v: [f64; 3]| (u[0] - v[0]).hypot(u[1] - v[1]);
            (d(a, b) + d(b, c) + d(c, a)) / 3.0
        })
        .filter(|l| l.is_finite())
        .sum();
    total / faces.len() as f64 >= EDGE_MIN_PIXELS * ss
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalized(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square as two triangles at z = 0.
    fn square() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        (
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    fn pixel(p: &Pixmap, x: u32, y: u32) -> Rgb {
        let c = p.pixel(x, y).unwrap();
        [c.red(), c.green(), c.blue()]
    }

    #[test]
    fn a_flat_square_from_above_shows_its_two_faces_and_their_edges() {
        let (v, f) = square();
        let style = Style::square(View::TOP, false, 64);
        let (red, blue) = ([200, 0, 0], [0, 0, 200]);
        let p = draw(&v, &f, &[red, blue], style, None).unwrap();
        assert_eq!((p.width(), p.height()), (64, 64));
        assert_eq!(pixel(&p, 0, 0), BACKGROUND, "margin");
        // y is down on the picture: face 0 (below the diagonal y = x) is at the lower right.
        assert_eq!(pixel(&p, 50, 48), red);
        assert_eq!(pixel(&p, 14, 16), blue);
        // The diagonal runs from (2.56, 61.44) to (61.44, 2.56): an edge line, darker.
        let d = pixel(&p, 31, 31);
        assert!(d[0] < 200 && d[2] < 200, "{d:?}");
    }

    #[test]
    fn a_checkerboard_shows_its_cells_inside_the_faces() {
        let (v, f) = square();
        // The initial map: the square itself, 12 cells across.
        let pattern = Pattern {
            points: &v,
            checker: Checker::Plane { cell: 1.0 / 12.0 },
        };
        let style = Style {
            view: View::TOP,
            lit: false,
            width: 128,
            height: 96,
        };
        let grey = [200, 200, 200];
        let p = draw(&v, &f, &[grey; 2], style, Some(pattern)).unwrap();
        assert_eq!((p.width(), p.height()), (128, 96));
        // The square spans 88.32 pixels from x = 19.84: a cell is 7.36 pixels. The centres
        // of two neighbouring cells on the middle row differ, diagonal neighbours match.
        let at = |i: f64, j: f64| {
            pixel(
                &p,
                (19.84 + 7.36 * (i + 0.5)) as u32,
                (3.84 + 7.36 * (j + 0.5)) as u32,
            )
        };
        assert_ne!(at(2.0, 5.0), at(3.0, 5.0));
        assert_eq!(at(2.0, 5.0), at(3.0, 6.0));
        assert!([at(2.0, 5.0), at(3.0, 5.0)].contains(&grey));
    }

    #[test]
    fn lighting_darkens_faces_turned_away_from_the_light() {
        let (v, f) = square();
        let colors = [[200, 200, 200]; 2];
        let flat = |view| {
            let s = Style::square(view, true, 64);
            // The commonest red value: the faces' interior.
            let p = draw(&v, &f, &colors, s, None).unwrap();
            let mut count = [0usize; 255];
            for c in p.pixels().iter().filter(|c| c.red() != 255) {
                count[usize::from(c.red())] += 1;
            }
            (0..255).max_by_key(|&r| count[r]).unwrap_or(0)
        };
        let facing = flat(View::TOP);
        let grazing = flat(View {
            azimuth: -90.0,
            elevation: 20.0,
        });
        assert!(
            facing < 200 && grazing > 0 && grazing < facing,
            "{facing} {grazing}"
        );
    }
}
