//! `demkit cartogram --png`: the cartogram drawn as a PNG picture (tiny-skia), each region
//! filled with its colour (even–odd, so holes stay open) and outlined, with a legend strip
//! below the map.

use crate::Failure;
use crate::render::font::{self, Align};
use demkit::apps::cartogram::Polygon;
use demkit::apps::cartogram::colours::Colouring;
use std::path::Path;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// The legend strip's height in pixels.
const LEGEND_HEIGHT: u32 = 64;

/// The blank border around the map, in pixels.
const MARGIN: f64 = 8.0;

/// Draws `coordinates` (one entry per region) coloured by `colouring` in a picture whose map
/// is `size` pixels along its longer side, and writes it to `path` (after the drawing
/// succeeded, atomically).
pub fn write(
    path: &Path,
    coordinates: &[Vec<Polygon>],
    colouring: &Colouring,
    size: usize,
) -> Result<(), Failure> {
    crate::render::write_png(path, draw(coordinates, colouring, size))
}

/// The picture, or `None` when it cannot be allocated.
pub fn draw(coordinates: &[Vec<Polygon>], colouring: &Colouring, size: usize) -> Option<Pixmap> {
    let pts = coordinates.iter().flatten().flatten().flatten();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pts {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    // Half extents: no overflow for coordinates near the largest f64.
    let half = [
        (0.5 * hi[0] - 0.5 * lo[0]).max(f64::MIN_POSITIVE),
        (0.5 * hi[1] - 0.5 * lo[1]).max(f64::MIN_POSITIVE),
    ];
    let inner = size as f64 - 2.0 * MARGIN;
    let k = inner / (2.0 * half[0].max(half[1]));
    let (w, h) = (
        (2.0 * half[0] * k + 2.0 * MARGIN).round().max(1.0) as u32,
        (2.0 * half[1] * k + 2.0 * MARGIN).round().max(1.0) as u32,
    );
    let mut pixmap = Pixmap::new(w.max(64), h + LEGEND_HEIGHT)?;
    pixmap.fill(Color::WHITE);
    let to_px = |p: [f64; 2]| {
        (
            (MARGIN + 2.0 * (0.5 * p[0] - 0.5 * lo[0]) * k) as f32,
            (MARGIN + 2.0 * (0.5 * hi[1] - 0.5 * p[1]) * k) as f32,
        )
    };
    let stroke = Stroke {
        width: (size as f32 / 1024.0).clamp(0.5, 1.5),
        ..Stroke::default()
    };
    let mut outline = Paint::default();
    outline.set_color_rgba8(51, 51, 51, 255);
    outline.anti_alias = true;
    for (i, polys) in coordinates.iter().enumerate() {
        let mut pb = PathBuilder::new();
        for ring in polys.iter().flatten() {
            for (j, &p) in ring.iter().enumerate() {
                let (x, y) = to_px(p);
                if j == 0 {
                    pb.move_to(x, y);
                } else {
                    pb.line_to(x, y);
                }
            }
            pb.close();
        }
        let Some(path) = pb.finish() else { continue };
        let c = colouring.fills.get(i).copied().unwrap_or([200, 200, 200]);
        let mut fill = Paint::default();
        fill.set_color_rgba8(c[0], c[1], c[2], 255);
        fill.anti_alias = true;
        pixmap.fill_path(&path, &fill, FillRule::EvenOdd, Transform::identity(), None);
        pixmap.stroke_path(&path, &outline, &stroke, Transform::identity(), None);
    }
    legend(&mut pixmap, colouring, h as f32);
    Some(pixmap)
}

/// The legend strip from `top`: the title, then the swatches with their labels.
fn legend(pixmap: &mut Pixmap, colouring: &Colouring, top: f32) {
    let ink = Color::from_rgba8(34, 34, 34, 255);
    font::draw_text(
        pixmap,
        &colouring.legend.title,
        MARGIN as f32,
        top + 4.0,
        Align::Left,
        2.0,
        ink,
    );
    // Labels of up to 8 characters (12 pixels each) stay apart.
    let (swatch, gap) = (84.0f32, 16.0f32);
    for (k, (c, label)) in colouring.legend.swatches.iter().enumerate() {
        let x = MARGIN as f32 + k as f32 * (swatch + gap);
        if let Some(r) = Rect::from_xywh(x, top + 22.0, swatch, 14.0) {
            let mut paint = Paint::default();
            paint.set_color_rgba8(c[0], c[1], c[2], 255);
            pixmap.fill_rect(r, &paint, Transform::identity(), None);
        }
        font::draw_text(
            pixmap,
            label,
            x + swatch / 2.0,
            top + 42.0,
            Align::Centre,
            2.0,
            ink,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use demkit::apps::cartogram::colours::{ColourBy, colour};

    #[test]
    fn regions_are_filled_with_their_colours_and_the_legend_drawn() {
        let sq = |x: f64| vec![vec![[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 1.0], [x, 1.0]]];
        let c = colour(ColourBy::Density, &[1.0, 100.0], &[1.0, 1.0], &[0.0; 2]);
        let p = draw(&[vec![sq(0.0)], vec![sq(1.0)]], &c, 256).unwrap();
        // The map 2:1 in 240 pixels plus the margins, then the legend.
        assert_eq!((p.width(), p.height()), (256, 120 + 16 + LEGEND_HEIGHT));
        let at = |x: u32, y: u32| {
            let c = p.pixel(x, y).unwrap();
            [c.red(), c.green(), c.blue()]
        };
        assert_eq!(at(64, 64), c.fills[0]);
        assert_eq!(at(192, 64), c.fills[1]);
        assert_eq!(at(2, 2), [255, 255, 255]);
    }
}
