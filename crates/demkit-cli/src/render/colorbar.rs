//! A vertical colour bar for ratios on a log scale: the colours from the bottom (the smallest
//! ratio) to the top, a thin frame, tick marks and their ratio labels on the right.

use super::font::{Align, draw_text};
use super::raster::Rgb;
use super::ticks::{label, log_ticks};
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// A colour scale: `color(t)` for t in [0, 1], where t = 0 is the ratio e^`lo` and t = 1 the
/// ratio e^`hi`; `lo` = `hi` is a single value (one colour, one tick).
#[derive(Clone, Copy)]
pub struct Scale {
    /// The colour of a position in [0, 1].
    pub color: fn(f64) -> Rgb,
    /// The log of the ratio at the bottom.
    pub lo: f64,
    /// The log of the ratio at the top.
    pub hi: f64,
}

impl Scale {
    /// Where the ratio `e^log_ratio` falls in [0, 1] (clamped; ½ for a single value).
    pub fn position(&self, log_ratio: f64) -> f64 {
        if self.hi > self.lo {
            ((log_ratio - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
        } else {
            0.5
        }
    }

    /// The ratios to mark, most important first: both ends, 1 when inside, then the
    /// 1–2–5 ratios between the ends (only the powers of ten when they span over two decades).
    pub fn ticks(&self) -> Vec<f64> {
        let (a, b) = (self.lo.exp(), self.hi.exp());
        if self.hi <= self.lo {
            return vec![a];
        }
        let mut t = vec![a, b];
        let between = log_ticks(a, b);
        if between.contains(&1.0) {
            t.push(1.0);
        }
        t.extend(between.into_iter().filter(|&v| v != 1.0));
        t
    }
}

/// Where the bar is drawn, in pixels.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// The bar's left side.
    pub left: f32,
    /// The bar's top.
    pub top: f32,
    /// The bar's width.
    pub width: f32,
    /// The bar's height.
    pub height: f32,
}

/// Draws the bar of `scale` in `frame` with its labelled ticks (font scale `text`); labels
/// that would overlap one already drawn are left out, in the order of [`Scale::ticks`].
pub fn draw(pixmap: &mut Pixmap, scale: &Scale, frame: Frame, text: f32) {
    let rows = frame.height.round().max(1.0) as usize;
    let mut paint = Paint {
        anti_alias: false,
        ..Paint::default()
    };
    for i in 0..rows {
        let t = 1.0 - (i as f64 + 0.5) / rows as f64;
        let t = if scale.hi > scale.lo { t } else { 0.5 };
        let [r, g, b] = (scale.color)(t);
        paint.set_color_rgba8(r, g, b, 255);
        let y = frame.top + i as f32 * frame.height / rows as f32;
        if let Some(rect) =
            Rect::from_xywh(frame.left, y, frame.width, frame.height / rows as f32 + 0.5)
        {
            pixmap.fill_rect(rect, &paint, Transform::identity(), None);
        }
    }
    let ink = Color::from_rgba8(20, 20, 20, 255);
    let (l, t, w, h) = (frame.left, frame.top, frame.width, frame.height);
    let right = l + w;
    stroke(
        pixmap,
        &[(l, t), (right, t), (right, t + h), (l, t + h), (l, t)],
        ink,
    );
    let tick = 3.0 * text + 2.0;
    let glyph = 7.0 * text;
    let mut taken: Vec<(f32, f32)> = Vec::new();
    for v in scale.ticks() {
        let y = t + h * (1.0 - scale.position(v.ln()) as f32);
        stroke(pixmap, &[(right, y), (right + tick, y)], ink);
        let (y0, y1) = (y - glyph / 2.0, y + glyph / 2.0);
        if taken
            .iter()
            .any(|&(a, b)| y0 < b + text * 2.0 && y1 > a - text * 2.0)
        {
            continue;
        }
        taken.push((y0, y1));
        let x = right + tick + 2.0 * text;
        draw_text(pixmap, &label(v), x, y0, Align::Left, text, ink);
    }
}

/// A polyline one pixel wide.
fn stroke(pixmap: &mut Pixmap, points: &[(f32, f32)], color: Color) {
    let mut pb = PathBuilder::new();
    for (i, &(x, y)) in points.iter().enumerate() {
        if i == 0 {
            pb.move_to(x, y);
        } else {
            pb.line_to(x, y);
        }
    }
    let Some(path) = pb.finish() else { return };
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = true;
    let s = Stroke {
        width: 1.0,
        ..Stroke::default()
    };
    pixmap.stroke_path(&path, &paint, &s, Transform::identity(), None);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::colormap::diverging;

    #[test]
    fn ticks_put_the_ends_and_one_first() {
        let s = |lo: f64, hi: f64| Scale {
            color: diverging,
            lo: lo.ln(),
            hi: hi.ln(),
        };
        let t = s(1.0 / 1.05, 1.05).ticks();
        assert_eq!(t.len(), 3);
        assert!((t[0] - 1.0 / 1.05).abs() < 1e-12 && (t[1] - 1.05).abs() < 1e-12);
        assert_eq!(t[2], 1.0);
        assert_eq!(s(0.1, 10.0).ticks()[2..], [1.0, 0.2, 0.5, 2.0, 5.0]);
        assert_eq!(s(0.3, 0.7).ticks()[2..], [0.5]);
        assert_eq!(s(1e-3, 1e3).ticks()[2..], [1.0, 0.01, 0.1, 10.0, 100.0]);
        assert_eq!(s(2.0, 2.0).ticks(), [2.0]);
        assert_eq!(s(2.0, 2.0).position(5.0), 0.5);
        assert_eq!(s(0.5, 2.0).position(0.0), 0.5);
        assert_eq!(s(0.5, 2.0).position(9.0), 1.0);
    }

    #[test]
    fn the_bar_runs_from_red_at_the_top_to_blue_at_the_bottom() {
        let mut p = Pixmap::new(120, 200).unwrap();
        p.fill(Color::WHITE);
        let scale = Scale {
            color: diverging,
            lo: -(2f64.ln()),
            hi: 2f64.ln(),
        };
        let frame = Frame {
            left: 10.0,
            top: 10.0,
            width: 20.0,
            height: 180.0,
        };
        draw(&mut p, &scale, frame, 1.0);
        let at = |y: u32| {
            let c = p.pixel(20, y).unwrap();
            [c.red(), c.green(), c.blue()]
        };
        assert!(at(15)[0] > at(15)[2], "{:?}", at(15));
        assert!(at(185)[2] > at(185)[0], "{:?}", at(185));
        assert!(at(100).iter().all(|&c| c > 230), "{:?}", at(100));
        // Labels: dark pixels right of the ticks, near the top, the middle and the bottom.
        let dark_row = |y0: u32, y1: u32| {
            (y0..y1).any(|y| (40..120).any(|x| p.pixel(x, y).unwrap().red() < 100))
        };
        assert!(dark_row(5, 16) && dark_row(95, 106) && dark_row(184, 195));
    }
}
