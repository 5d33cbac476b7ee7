//! The colours of a cartogram's regions in its pictures, with the legend that explains them:
//! by density (value per input area, a logarithmic ramp from pale yellow to dark blue) or by
//! share error (a diverging ramp: blue too small, white on target, red too large).

/// An RGB colour.
pub type Rgb = [u8; 3];

/// What colours the regions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourBy {
    /// The value per input area, on a logarithmic scale.
    Density,
    /// The relative error of the region's share, symmetric around 0.
    Error,
}

/// The regions' colours and their legend.
#[derive(Debug, Clone, PartialEq)]
pub struct Colouring {
    /// One colour per region.
    pub fills: Vec<Rgb>,
    /// What the colours mean.
    pub legend: Legend,
}

/// A legend: a title and swatches, each with its label.
#[derive(Debug, Clone, PartialEq)]
pub struct Legend {
    /// What the colours show (lowercase letters, as the pictures' font has them).
    pub title: String,
    /// Colour and label, from the lowest value to the highest.
    pub swatches: Vec<(Rgb, String)>,
}

/// Swatches in a legend.
const SWATCHES: usize = 5;

/// The colours of regions with `values`, input areas `areas` (any unit) and share errors
/// `errors`, as `by` says. Densities that are not finite and positive (an area beyond the
/// range of `f64`) fall back to the values themselves; a range that is one value gets the
/// ramp's middle.
pub fn colour(by: ColourBy, values: &[f64], areas: &[f64], errors: &[f64]) -> Colouring {
    match by {
        ColourBy::Density => {
            let mut d: Vec<f64> = values.iter().zip(areas).map(|(v, a)| v / a).collect();
            let mut title = "density";
            if !d.iter().all(|x| x.is_finite() && *x > 0.0) {
                d = values.to_vec();
                title = "value";
            }
            let (lo, hi) = d
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            let t = |x: f64| {
                if hi > lo {
                    (x / lo).ln() / (hi / lo).ln()
                } else {
                    0.5
                }
            };
            let swatches = (0..SWATCHES)
                .map(|k| {
                    let s = k as f64 / (SWATCHES - 1) as f64;
                    let x = if hi > lo { lo * (hi / lo).powf(s) } else { lo };
                    (sequential(s), number(x))
                })
                .collect();
            Colouring {
                fills: d.iter().map(|&x| sequential(t(x))).collect(),
                legend: Legend {
                    title: title.into(),
                    swatches,
                },
            }
        }
        ColourBy::Error => {
            let span = errors
                .iter()
                .filter(|e| e.is_finite())
                .fold(0.0f64, |m, e| m.max(e.abs()))
                .max(1e-6);
            let swatches = (0..SWATCHES)
                .map(|k| {
                    let s = 2.0 * k as f64 / (SWATCHES - 1) as f64 - 1.0;
                    (diverging(s), number(s * span))
                })
                .collect();
            Colouring {
                fills: errors
                    .iter()
                    .map(|&e| diverging(if e.is_finite() { e / span } else { 1.0 }))
                    .collect(),
                legend: Legend {
                    title: "share error".into(),
                    swatches,
                },
            }
        }
    }
}

/// A number in 3 significant digits, in the pictures' font (digits, '.', '-', 'e').
fn number(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

/// A ramp from pale yellow (t = 0) to dark blue (t = 1).
pub fn sequential(t: f64) -> Rgb {
    let t = t.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * t).round() as u8;
    [lerp(255.0, 8.0), lerp(247.0, 64.0), lerp(188.0, 129.0)]
}

/// Blue (s = −1) through white (0) to red (1).
pub fn diverging(s: f64) -> Rgb {
    let s = s.clamp(-1.0, 1.0);
    let (end, t) = if s < 0.0 {
        ([33.0, 102.0, 172.0], -s)
    } else {
        ([178.0, 24.0, 43.0], s)
    };
    let lerp = |b: f64| (247.0 + (b - 247.0) * t).round() as u8;
    [lerp(end[0]), lerp(end[1]), lerp(end[2])]
}

/// `#rrggbb`.
pub fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_span_the_ramp_and_errors_are_symmetric() {
        let c = colour(
            ColourBy::Density,
            &[1.0, 10.0, 100.0],
            &[1.0, 1.0, 1.0],
            &[0.0; 3],
        );
        assert_eq!(
            c.fills,
            vec![sequential(0.0), sequential(0.5), sequential(1.0)]
        );
        assert_eq!(c.legend.title, "density");
        let labels: Vec<&str> = c.legend.swatches.iter().map(|s| s.1.as_str()).collect();
        assert_eq!(labels, ["1.00", "3.16", "10.0", "31.6", "100"]);
        let c = colour(ColourBy::Error, &[1.0; 3], &[1.0; 3], &[-0.02, 0.0, 0.01]);
        assert_eq!(c.fills[0], diverging(-1.0));
        assert_eq!(c.fills[1], [247, 247, 247]);
        assert_eq!(c.legend.swatches[0].1, "-0.0200");
        assert_eq!(c.legend.swatches[2].1, "0");
        // Areas beyond f64: coloured by value.
        let c = colour(
            ColourBy::Density,
            &[1.0, 2.0],
            &[f64::INFINITY; 2],
            &[0.0; 2],
        );
        assert_eq!(c.legend.title, "value");
    }
}
