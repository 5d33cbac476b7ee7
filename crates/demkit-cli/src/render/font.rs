//! A tiny 5 × 7 bitmap font (digits, a few signs and the lowercase letters the plots use) for
//! axis labels; tiny-skia draws no text. Unknown characters are blank.

use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Transform};

/// The glyphs, 7 rows of 5 columns each ('#' is ink).
#[rustfmt::skip]
const GLYPHS: &[(char, [&str; 7])] = &[
    ('0', [".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."]),
    ('1', ["..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."]),
    ('2', [".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"]),
    ('3', ["#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."]),
    ('4', ["...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."]),
    ('5', ["#####", "#....", "####.", "....#", "....#", "#...#", ".###."]),
    ('6', ["..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."]),
    ('7', ["#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."]),
    ('8', [".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."]),
    ('9', [".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."]),
    ('.', [".....", ".....", ".....", ".....", ".....", ".##..", ".##.."]),
    ('/', [".....", "....#", "...#.", "..#..", ".#...", "#....", "....."]),
    ('-', [".....", ".....", ".....", ".###.", ".....", ".....", "....."]),
    ('a', [".....", ".....", ".###.", "....#", ".####", "#...#", ".####"]),
    ('c', [".....", ".....", ".###.", "#....", "#....", "#...#", ".###."]),
    ('d', ["....#", "....#", ".##.#", "#..##", "#...#", "#...#", ".####"]),
    ('e', [".....", ".....", ".###.", "#...#", "#####", "#....", ".###."]),
    ('f', ["..##.", ".#..#", ".#...", "###..", ".#...", ".#...", ".#..."]),
    ('g', [".....", ".....", ".####", "#...#", ".####", "....#", ".###."]),
    ('h', ["#....", "#....", "#.##.", "##..#", "#...#", "#...#", "#...#"]),
    ('i', ["..#..", ".....", ".##..", "..#..", "..#..", "..#..", ".###."]),
    ('l', [".##..", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."]),
    ('m', [".....", ".....", "##.#.", "#.#.#", "#.#.#", "#...#", "#...#"]),
    ('n', [".....", ".....", "#.##.", "##..#", "#...#", "#...#", "#...#"]),
    ('o', [".....", ".....", ".###.", "#...#", "#...#", "#...#", ".###."]),
    ('p', [".....", ".....", "####.", "#...#", "#...#", "####.", "#...."]),
    ('r', [".....", ".....", "#.##.", "##..#", "#....", "#....", "#...."]),
    ('s', [".....", ".....", ".###.", "#....", ".###.", "....#", "####."]),
    ('t', [".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##."]),
    ('u', [".....", ".....", "#...#", "#...#", "#...#", "#..##", ".##.#"]),
    ('x', [".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#"]),
    ('y', [".....", ".....", "#...#", "#...#", ".#.#.", "..#..", "##..."]),
];

/// Where a text is placed relative to the given point (its top edge, vertically).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Align {
    /// The point is the left end.
    Left,
    /// The point is the middle.
    Centre,
    /// The point is the right end.
    Right,
}

/// The width in pixels of `text` drawn with `scale` pixels per font pixel.
pub fn text_width(text: &str, scale: f32) -> f32 {
    let n = text.chars().count() as f32;
    if n == 0.0 {
        0.0
    } else {
        (6.0 * n - 1.0) * scale
    }
}

/// The ink of `c`: (column, row) of every lit font pixel.
fn ink(c: char) -> Vec<(usize, usize)> {
    let Some((_, rows)) = GLYPHS.iter().find(|(g, _)| *g == c) else {
        return Vec::new();
    };
    rows.iter()
        .enumerate()
        .flat_map(|(y, row)| {
            row.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'#')
                .map(move |(x, _)| (x, y))
        })
        .collect()
}

/// Draws `text` with its top edge at `y`, `scale` pixels per font pixel.
pub fn draw_text(
    pixmap: &mut Pixmap,
    text: &str,
    x: f32,
    y: f32,
    align: Align,
    scale: f32,
    color: Color,
) {
    let left = match align {
        Align::Left => x,
        Align::Centre => x - text_width(text, scale) / 2.0,
        Align::Right => x - text_width(text, scale),
    };
    let mut pb = PathBuilder::new();
    for (i, c) in text.chars().enumerate() {
        let x0 = left + 6.0 * scale * i as f32;
        for (cx, cy) in ink(c) {
            if let Some(r) = tiny_skia::Rect::from_xywh(
                x0 + cx as f32 * scale,
                y + cy as f32 * scale,
                scale,
                scale,
            ) {
                pb.push_rect(r);
            }
        }
    }
    if let Some(path) = pb.finish() {
        let mut paint = Paint::default();
        paint.set_color(color);
        paint.anti_alias = false;
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_glyph_is_five_by_seven_and_has_ink() {
        for (c, rows) in GLYPHS {
            assert!(rows.iter().all(|r| r.len() == 5), "{c}");
            assert!(!ink(*c).is_empty(), "{c}");
        }
        assert!(ink('?').is_empty());
    }

    #[test]
    fn text_lands_where_aligned() {
        assert_eq!(text_width("", 2.0), 0.0);
        assert_eq!(text_width("10", 2.0), 22.0);
        let mut p = Pixmap::new(40, 20).unwrap();
        p.fill(Color::WHITE);
        draw_text(&mut p, "1", 20.0, 5.0, Align::Right, 1.0, Color::BLACK);
        let dark = |x: u32, y: u32| p.pixel(x, y).unwrap().red() < 128;
        // '1' spans columns 15..20; its stem is column 2 → x = 17, rows 5..12.
        assert!(dark(17, 5) && dark(17, 11));
        assert!(!dark(17, 13) && !dark(21, 8) && !dark(10, 8));
    }
}
