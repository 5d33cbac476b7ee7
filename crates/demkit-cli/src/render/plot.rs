//! The two-panel histogram figure: the initial and the final normalized face density, same
//! bins and same axes, bars over light grid lines, a dashed line at ratio 1, labelled ticks.

use super::font::text_width;
use super::font::{Align, draw_text};
use super::histogram::{Axis, BINS};
use super::ticks::{label, nice_top};
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform};

/// Bar colours of the initial and the final panel.
const BARS: [(u8, u8, u8); 2] = [(76, 114, 176), (221, 132, 82)];

/// A rectangle of the picture in pixels.
#[derive(Debug, Clone, Copy)]
struct Frame {
    left: f32,
    right: f32,
    top: f32,
    bottom: f32,
}

/// The figure (`1.5·size` × `size` pixels) for the normalized densities `initial` and `final_`.
pub fn histograms(initial: &[f64], final_: &[f64], size: usize) -> Option<Pixmap> {
    let (w, h) = (size * 3 / 2, size);
    let mut pixmap = Pixmap::new(w as u32, h as u32)?;
    pixmap.fill(Color::WHITE);
    let axis = Axis::fit(&[initial, final_], BINS);
    let sets = [initial, final_];
    let fractions: Vec<Vec<f64>> = sets
        .iter()
        .map(|s| {
            let n = s.len().max(1) as f64;
            axis.counts(s).iter().map(|&c| c as f64 / n).collect()
        })
        .collect();
    let top = fractions.iter().flatten().copied().fold(0.0, f64::max);
    let (y_top, y_step) = nice_top(top);
    let scale = (size as f32 / 340.0).max(1.0).round();
    let (w, h) = (w as f32, h as f32);
    for (k, title) in ["initial map", "final map"].into_iter().enumerate() {
        let x0 = k as f32 * w / 2.0;
        let pw = w / 2.0;
        let frame = Frame {
            left: x0 + 0.16 * pw,
            right: x0 + 0.93 * pw,
            top: 0.14 * h,
            bottom: 0.84 * h,
        };
        panel(
            &mut pixmap,
            frame,
            &fractions[k],
            BARS[k],
            &axis,
            (y_top, y_step),
            scale,
        );
        let ink = Color::from_rgba8(20, 20, 20, 255);
        let mid = (frame.left + frame.right) / 2.0;
        draw_text(
            &mut pixmap,
            title,
            mid,
            0.035 * h,
            Align::Centre,
            scale + 1.0,
            ink,
        );
        draw_text(
            &mut pixmap,
            "fraction of faces",
            frame.left,
            frame.top - 12.0 * scale,
            Align::Left,
            scale,
            ink,
        );
        draw_text(
            &mut pixmap,
            "density / mean density",
            mid,
            0.93 * h,
            Align::Centre,
            scale,
            ink,
        );
    }
    Some(pixmap)
}

/// One panel: grid, bars, reference line at 1, axes, ticks and their labels.
fn panel(
    pixmap: &mut Pixmap,
    f: Frame,
    fractions: &[f64],
    bar: (u8, u8, u8),
    axis: &Axis,
    (y_top, y_step): (f64, f64),
    scale: f32,
) {
    let (lo, hi) = axis.ends();
    let x_of = |v: f64| f.left + (f.right - f.left) * ((v.ln() - lo) / (hi - lo)) as f32;
    let y_of = |v: f64| f.bottom - (f.bottom - f.top) * (v / y_top) as f32;
    let ink = Color::from_rgba8(20, 20, 20, 255);
    let tick = 6.0 * scale / 3.0 + 4.0;
    // Horizontal grid lines and the count ticks.
    let n_steps = (y_top / y_step).round() as usize;
    for i in 0..=n_steps {
        let v = y_step * i as f64;
        let y = y_of(v);
        if i > 0 {
            line(
                pixmap,
                (f.left, y),
                (f.right, y),
                Color::from_rgba8(225, 225, 225, 255),
                1.0,
                None,
            );
        }
        line(pixmap, (f.left - tick, y), (f.left, y), ink, 1.5, None);
        draw_text(
            pixmap,
            &label(v),
            f.left - tick - 3.0 * scale,
            y - 3.5 * scale,
            Align::Right,
            scale,
            ink,
        );
    }
    // The bars.
    let mut paint = Paint::default();
    paint.set_color_rgba8(bar.0, bar.1, bar.2, 255);
    paint.anti_alias = true;
    let bin_w = (f.right - f.left) / fractions.len() as f32;
    for (i, &v) in fractions.iter().enumerate() {
        if v <= 0.0 {
            continue;
        }
        let x = f.left + bin_w * i as f32;
        let y = y_of(v);
        let gap = if bin_w > 6.0 { 1.0 } else { 0.0 };
        if let Some(r) = Rect::from_ltrb(x + gap / 2.0, y, x + bin_w - gap / 2.0, f.bottom) {
            pixmap.fill_rect(r, &paint, Transform::identity(), None);
        }
    }
    // Ratio 1: a dashed line.
    let x1 = x_of(1.0);
    let dash = StrokeDash::new(vec![8.0, 6.0], 0.0);
    line(
        pixmap,
        (x1, f.top),
        (x1, f.bottom),
        Color::from_rgba8(90, 90, 90, 255),
        1.5,
        dash,
    );
    // Axes and the density ticks.
    line(
        pixmap,
        (f.left, f.bottom),
        (f.right, f.bottom),
        ink,
        2.0,
        None,
    );
    line(pixmap, (f.left, f.top), (f.left, f.bottom), ink, 2.0, None);
    // Every tick gets its mark; labels go outward from 1, skipping any that would overlap
    // its neighbour.
    let ticks = axis.ticks();
    for &v in &ticks {
        let x = x_of(v);
        line(pixmap, (x, f.bottom), (x, f.bottom + tick), ink, 1.5, None);
    }
    let one = ticks.iter().position(|&v| v == 1.0).unwrap_or(0);
    let gap = 4.0 * scale;
    let extent = |v: f64| {
        let half = text_width(&label(v), scale) / 2.0;
        (x_of(v) - half, x_of(v) + half)
    };
    let mut shown = vec![one];
    let mut edge = extent(ticks[one]).1;
    for (i, &v) in ticks.iter().enumerate().skip(one + 1) {
        if extent(v).0 >= edge + gap {
            shown.push(i);
            edge = extent(v).1;
        }
    }
    let mut edge = extent(ticks[one]).0;
    for (i, &v) in ticks.iter().enumerate().take(one).rev() {
        if extent(v).1 <= edge - gap {
            shown.push(i);
            edge = extent(v).0;
        }
    }
    for i in shown {
        let v = ticks[i];
        draw_text(
            pixmap,
            &label(v),
            x_of(v),
            f.bottom + tick + 3.0 * scale,
            Align::Centre,
            scale,
            ink,
        );
    }
}

/// A straight line of `width` pixels, optionally dashed.
fn line(
    pixmap: &mut Pixmap,
    a: (f32, f32),
    b: (f32, f32),
    color: Color,
    width: f32,
    dash: Option<StrokeDash>,
) {
    let mut pb = PathBuilder::new();
    pb.move_to(a.0, a.1);
    pb.line_to(b.0, b.1);
    let Some(path) = pb.finish() else { return };
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = true;
    let stroke = Stroke {
        width,
        dash,
        ..Stroke::default()
    };
    pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colour_count(p: &Pixmap, c: (u8, u8, u8)) -> usize {
        p.pixels()
            .iter()
            .filter(|x| (x.red(), x.green(), x.blue()) == c)
            .count()
    }

    #[test]
    fn a_spread_initial_and_a_spike_final() {
        let initial: Vec<f64> = (0..400).map(|i| 0.5 + f64::from(i) / 400.0).collect();
        let final_ = vec![1.0; 400];
        let p = histograms(&initial, &final_, 512).unwrap();
        assert_eq!((p.width(), p.height()), (768, 512));
        let (a, b) = (colour_count(&p, BARS[0]), colour_count(&p, BARS[1]));
        // Both panels have bars: the spike is one bin of full height (358 px tall, 5 px
        // wide of which anti-aliasing leaves at least 2 columns exactly the bar colour).
        assert!(a > 500 && b > 700, "{a} {b}");
        // The left half holds only initial bars, the right half only final ones.
        let left_b = p
            .pixels()
            .chunks(768)
            .flat_map(|row| &row[..384])
            .filter(|x| (x.red(), x.green(), x.blue()) == BARS[1])
            .count();
        assert_eq!(left_b, 0);
    }
}
