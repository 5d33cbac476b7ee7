//! A cartogram drawn as SVG: one path per feature (even–odd fill, so holes stay open), filled
//! by value on a logarithmic colour ramp, with a thin border; the view box fits the drawing.

use super::Polygon;
use std::fmt::Write;

/// The SVG text of `coordinates` (one entry per feature) filled by `values`; y points up in
/// the data and down in SVG, so it is negated.
pub fn render(coordinates: &[Vec<Polygon>], values: &[f64]) -> String {
    let pts = coordinates.iter().flatten().flatten().flatten();
    let (lo, hi) = super::regions::bbox(pts.copied());
    let (w, h) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
    let pad = 0.02 * w.max(h);
    let stroke = 0.002 * w.max(h);
    let (vmin, vmax) = values
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{} {} {} {}" width="800" height="{}">"#,
        lo[0] - pad,
        -hi[1] - pad,
        w + 2.0 * pad,
        h + 2.0 * pad,
        (800.0 * (h + 2.0 * pad) / (w + 2.0 * pad)).round().max(1.0)
    );
    for (polys, &v) in coordinates.iter().zip(values) {
        let t = if vmax > vmin {
            (v / vmin).ln() / (vmax / vmin).ln()
        } else {
            0.5
        };
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
            colour(t),
            stroke
        );
    }
    s.push_str("</svg>\n");
    s
}

/// A ramp from pale yellow (t = 0) to dark blue (t = 1).
fn colour(t: f64) -> String {
    let t = t.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * t).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        lerp(255.0, 8.0),
        lerp(247.0, 64.0),
        lerp(188.0, 129.0)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_path_per_feature_in_a_fitted_view_box() {
        let sq = vec![vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]];
        let svg = render(&[vec![sq.clone()], vec![sq]], &[1.0, 10.0]);
        assert_eq!(svg.matches("<path").count(), 2);
        assert!(svg.contains(r#"viewBox="-0.04 -1.04 2.08 1.08""#), "{svg}");
        assert!(svg.contains("#fff7bc") && svg.contains("#084081"));
    }
}
