//! A cartogram drawn as SVG: one path per feature (even–odd fill, so holes stay open), filled
//! with the region's colour ([`super::colours`]), with a thin border; the map's view box fits
//! the drawing, and a legend below it shows what the colours mean.

use super::Polygon;
use super::colours::{Colouring, hex};
use std::fmt::Write;

/// The picture's width in pixels.
const WIDTH: f64 = 800.0;

/// The legend's height in pixels, below the map.
const LEGEND_HEIGHT: f64 = 56.0;

/// The SVG text of `coordinates` (one entry per feature) filled with `colouring`'s colours;
/// y points up in the data and down in SVG, so it is negated.
pub fn render(coordinates: &[Vec<Polygon>], colouring: &Colouring) -> String {
    let pts = coordinates.iter().flatten().flatten().flatten();
    let (lo, hi) = super::regions::bbox(pts.copied());
    let (w, h) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
    let pad = 0.02 * w.max(h);
    let stroke = 0.002 * w.max(h);
    let map_height = (WIDTH * (h + 2.0 * pad) / (w + 2.0 * pad)).round().max(1.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{}">"#,
        map_height + LEGEND_HEIGHT
    );
    let _ = writeln!(
        s,
        r#"<svg viewBox="{} {} {} {}" width="{WIDTH}" height="{map_height}">"#,
        lo[0] - pad,
        -hi[1] - pad,
        w + 2.0 * pad,
        h + 2.0 * pad,
    );
    for (i, polys) in coordinates.iter().enumerate() {
        let fill = colouring.fills.get(i).copied().unwrap_or([200, 200, 200]);
        let mut d = String::new();
        for ring in polys.iter().flatten() {
            for (i, p) in ring.iter().enumerate() {
                let _ = write!(d, "{}{} {} ", if i == 0 { 'M' } else { 'L' }, p[0], -p[1]);
            }
            d.push_str("Z ");
        }
        let _ = writeln!(
            s,
            r##"<path d="{}" fill="{}" fill-rule="evenodd" stroke="#333" stroke-width="{}"/>"##,
            d.trim_end(),
            hex(fill),
            stroke
        );
    }
    s.push_str("</svg>\n");
    legend(&mut s, colouring, map_height);
    s.push_str("</svg>\n");
    s
}

/// The legend box: the title, then the swatches side by side with their labels below.
fn legend(s: &mut String, colouring: &Colouring, top: f64) {
    let legend = &colouring.legend;
    let (swatch, gap) = (48.0, 4.0);
    let width = 16.0 + legend.swatches.len() as f64 * (swatch + gap);
    let _ = writeln!(
        s,
        r##"<g class="legend" font-family="sans-serif" font-size="11" fill="#222"><rect x="4" y="{}" width="{width}" height="{}" fill="#fff" stroke="#999"/>"##,
        top + 2.0,
        LEGEND_HEIGHT - 6.0
    );
    let _ = writeln!(
        s,
        r#"<text x="12" y="{}">{}</text>"#,
        top + 16.0,
        escape(&legend.title)
    );
    for (k, (colour, label)) in legend.swatches.iter().enumerate() {
        let x = 12.0 + k as f64 * (swatch + gap);
        let _ = writeln!(
            s,
            r##"<rect x="{x}" y="{}" width="{swatch}" height="12" fill="{}" stroke="#666"/><text x="{}" y="{}" text-anchor="middle">{}</text>"##,
            top + 22.0,
            hex(*colour),
            x + swatch / 2.0,
            top + 46.0,
            escape(label)
        );
    }
    s.push_str("</g>\n");
}

/// Text with XML's special characters escaped.
fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::super::colours::{ColourBy, colour};
    use super::*;

    #[test]
    fn one_path_per_feature_in_a_fitted_view_box_with_a_legend() {
        let sq = vec![vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]];
        let c = colour(ColourBy::Density, &[1.0, 10.0], &[2.0, 2.0], &[0.0, 0.0]);
        let svg = render(&[vec![sq.clone()], vec![sq]], &c);
        assert_eq!(svg.matches("<path").count(), 2);
        assert!(svg.contains(r#"viewBox="-0.04 -1.04 2.08 1.08""#), "{svg}");
        assert!(svg.contains("#fff7bc") && svg.contains("#084081"));
        assert!(
            svg.contains(">density</text>") && svg.contains(">5.00</text>"),
            "{svg}"
        );
        assert_eq!(svg.matches("<svg").count(), svg.matches("</svg>").count());
    }
}
