//! The `map --render` figure: two panels side by side, each a square picture of a mesh with a
//! legend strip on its right (a title, the caption "density / mean" and a colour bar).
//!
//! ```text
//! +-----------+-------+-----------+-------+
//! |           | input |           | map   |
//! |  input    | ▇ 2   |  final    | ▇ 1.05|
//! |  surface  | ▇ 1   |  map      | ▇ 1   |
//! |           | ▇ 0.5 |           | ▇ 0.95|
//! +-----------+-------+-----------+-------+
//!    N × N      strip    N × N      strip
//! ```

use super::colorbar::{self, Scale};
use super::font::{Align, draw_text, text_width};
use super::raster::Rgb;
use super::scene::{self, Pattern, Style};
use tiny_skia::{Color, Pixmap, PixmapPaint, Transform};

/// One panel: a mesh, its face colours and how to draw it, and its legend.
pub struct Panel<'a> {
    /// The vertex positions drawn.
    pub positions: &'a [[f64; 3]],
    /// The faces.
    pub faces: &'a [[u32; 3]],
    /// One colour per face.
    pub colors: Vec<Rgb>,
    /// The view, lighting (and the square size, replaced by the figure's).
    pub style: Style,
    /// The checkerboard carried by the mesh, if any.
    pub pattern: Option<Pattern<'a>>,
    /// The title above the legend.
    pub title: &'a str,
    /// The colour scale of the legend.
    pub scale: Scale,
    /// A word under the bar (e.g. "uniform"), if any.
    pub note: Option<&'a str>,
}

/// Pixels per font pixel of labels in a figure of panels `size` pixels high.
fn text_scale(size: usize) -> f32 {
    (size as f32 / 340.0).round().max(1.0)
}

/// The widest label a bar may carry, for the strip's width.
const WIDEST_LABEL: &str = "0.0012";

/// The longest title.
const WIDEST_TITLE: &str = "input";

/// The width of the legend strip beside a panel `size` pixels high.
pub fn strip_width(size: usize) -> usize {
    let (ts, pad) = (text_scale(size), margin(size));
    let bar = bar_width(size) + 3.0 * ts + 2.0 + 2.0 * ts + text_width(WIDEST_LABEL, ts);
    let title = text_width(WIDEST_TITLE, ts + 1.0);
    (2.0 * pad + bar.max(title)).ceil() as usize
}

fn margin(size: usize) -> f32 {
    (0.02 * size as f32).max(3.0)
}

fn bar_width(size: usize) -> f32 {
    (0.04 * size as f32).max(6.0)
}

/// The figure: the panels side by side, each `size` × `size` pixels plus its legend strip.
pub fn draw(panels: &[Panel], size: usize) -> Option<Pixmap> {
    let strip = strip_width(size);
    let panel_width = size + strip;
    let mut figure = Pixmap::new((panel_width * panels.len()) as u32, size as u32)?;
    figure.fill(Color::WHITE);
    for (k, p) in panels.iter().enumerate() {
        let style = Style {
            width: size,
            height: size,
            ..p.style
        };
        let picture = scene::draw(p.positions, p.faces, &p.colors, style, p.pattern)?;
        let x0 = (k * panel_width) as i32;
        figure.draw_pixmap(
            x0,
            0,
            picture.as_ref(),
            &PixmapPaint::default(),
            Transform::identity(),
            None,
        );
        legend(&mut figure, p, (x0 + size as i32) as f32, size);
    }
    Some(figure)
}

/// The legend strip starting at `x`: title, caption, bar, note.
fn legend(figure: &mut Pixmap, p: &Panel, x: f32, size: usize) {
    let (ts, pad, s) = (text_scale(size), margin(size), size as f32);
    let ink = Color::from_rgba8(20, 20, 20, 255);
    let left = x + pad;
    let mut y = 0.04 * s;
    draw_text(figure, p.title, left, y, Align::Left, ts + 1.0, ink);
    y += 7.0 * (ts + 1.0) + 4.0 * ts;
    for line in ["density", "/ mean"] {
        draw_text(figure, line, left, y, Align::Left, ts, ink);
        y += 10.0 * ts;
    }
    let top = y + 6.0 * ts;
    let bottom = 0.9 * s;
    let frame = colorbar::Frame {
        left,
        top,
        width: bar_width(size),
        height: (bottom - top).max(8.0),
    };
    colorbar::draw(figure, &p.scale, frame, ts);
    if let Some(note) = p.note {
        draw_text(
            figure,
            note,
            left,
            frame.top + frame.height + 4.0 * ts,
            Align::Left,
            ts,
            ink,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::camera::View;
    use crate::render::colormap::diverging;

    #[test]
    fn two_panels_side_by_side_with_their_legends() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
        let f = [[0u32, 1, 2]];
        let scale = Scale {
            color: diverging,
            lo: -0.1,
            hi: 0.1,
        };
        let panel = |c: Rgb| Panel {
            positions: &v,
            faces: &f,
            colors: vec![c],
            style: Style::square(View::TOP, false, 1),
            pattern: None,
            title: "map",
            scale,
            note: None,
        };
        let size = 256;
        let p = draw(&[panel([200, 0, 0]), panel([0, 0, 200])], size).unwrap();
        let strip = strip_width(size);
        assert_eq!((p.width() as usize, p.height()), (2 * (size + strip), 256));
        let rgb = |x: usize, y: u32| {
            let c = p.pixel(x as u32, y).unwrap();
            [c.red(), c.green(), c.blue()]
        };
        // Each triangle in its own panel (lower right of the square), the legends white
        // where nothing is drawn.
        assert_eq!(rgb(200, 200), [200, 0, 0]);
        assert_eq!(rgb(size + strip + 200, 200), [0, 0, 200]);
        assert_eq!(rgb(size + strip - 2, 5), [255, 255, 255]);
    }
}
