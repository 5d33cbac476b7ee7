//! What `map --render` shows: the input surface coloured by its population density, and the
//! final map coloured by the density left after the map, side by side ([`figure`]).
//!
//! - Left, "input": each face's P(T)/A(T) over ΣP/ΣA with A on the input surface (viridis,
//!   log scale between the 0.5 % and 99.5 % quantiles). A constant density (population
//!   `area`) is one colour and the legend says "uniform".
//! - Right, "map": each face's P(T)/A_map(T) over ΣP/ΣA_map, A_map its area on the map, on a
//!   log scale centred on 1 (diverging: blue below, near-white at 1, red above) up to the
//!   first of 1.01, 1.02, 1.05, 1.1, … holding the 0.5 % and 99.5 % quantiles both ways.
//!
//! Both carry the same checkerboard, laid out on the initial map ([`super::checker`]): on the
//! right, a cell's area compared with the left is what the map did to it.

use super::View;
use super::checker::{Checker, Kind};
use super::colorbar::Scale;
use super::colormap::{diverging, quantile_range, viridis};
use super::figure::{self, Panel};
use super::histogram::normalized_densities;
use super::raster::Rgb;
use super::scene::Pattern;
use demkit::TriMesh;
use demkit::geometry::face_areas;
use demkit::metrics::{Domain, map_areas};
use tiny_skia::Pixmap;

/// The half-ranges of the map's scale: it runs from 1/R to R for the first R that holds the
/// densities.
const RATIOS: [f64; 13] = [
    1.01, 1.02, 1.05, 1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0, 100.0, 1e3, 1e4,
];

/// Input densities whose logs span less than this are drawn as uniform.
const UNIFORM: f64 = 1e-6;

/// The figure of `map` (of the surface `mesh`, the one the map is of), panels `size` pixels
/// high, seen from `view` (default: each panel's own, as `demkit render` picks it).
pub fn figure(
    mesh: &TriMesh,
    map: &demkit::Map,
    view: Option<View>,
    size: usize,
) -> Option<Pixmap> {
    let faces = &mesh.faces;
    let domain = map.metrics_domain();
    let kind = match domain {
        Domain::Plane => Kind::Plane,
        Domain::Sphere => Kind::Sphere,
        Domain::Torus { .. } => Kind::Torus,
    };
    let initial = &map.result.initial;
    let pattern = Pattern {
        points: initial,
        checker: Checker::fit(initial, kind),
    };
    let before = log_densities(&map.population, &face_areas(&mesh.positions, faces));
    let (areas, _) = map_areas(&map.result.positions, faces, domain);
    let after = log_densities(&map.population, &areas);
    let (input, uniform) = input_scale(&before);
    let output = residual_scale(&after);
    let positions = &map.result.positions;
    let panels = [
        Panel {
            positions: &mesh.positions,
            faces,
            colors: colors(&input, &before),
            style: super::scene_style(&mesh.positions, view, size),
            pattern: Some(pattern),
            title: "input",
            scale: input,
            note: uniform.then_some("uniform"),
        },
        Panel {
            positions,
            faces,
            colors: colors(&output, &after),
            style: super::scene_style(positions, view, size),
            pattern: Some(pattern),
            title: "map",
            scale: output,
            note: None,
        },
    ];
    figure::draw(&panels, size)
}

/// The log of each face's density P/A over the mean ΣP/ΣA.
pub fn log_densities(population: &[f64], areas: &[f64]) -> Vec<f64> {
    normalized_densities(population, areas)
        .iter()
        .map(|d| d.ln())
        .collect()
}

/// The colour of each log density on `scale`.
fn colors(scale: &Scale, logs: &[f64]) -> Vec<Rgb> {
    logs.iter()
        .map(|&l| (scale.color)(scale.position(l)))
        .collect()
}

/// The input's scale: viridis between the quantiles of the log densities; a single value
/// (and `true`) when they span less than [`UNIFORM`].
pub fn input_scale(logs: &[f64]) -> (Scale, bool) {
    let (lo, hi) = quantile_range(logs).unwrap_or((0.0, 0.0));
    if hi - lo < UNIFORM {
        let mid = (lo + hi) / 2.0;
        let single = Scale {
            color: viridis,
            lo: mid,
            hi: mid,
        };
        return (single, true);
    }
    (
        Scale {
            color: viridis,
            lo,
            hi,
        },
        false,
    )
}

/// The map's scale: diverging, from 1/R to R for the first R of [`RATIOS`] holding the
/// quantiles of the log densities both ways (the last when none does).
pub fn residual_scale(logs: &[f64]) -> Scale {
    let (lo, hi) = quantile_range(logs).unwrap_or((0.0, 0.0));
    let need = lo.abs().max(hi.abs()).exp();
    let r = RATIOS
        .iter()
        .copied()
        .find(|&r| r >= need * (1.0 - 1e-12))
        .unwrap_or(RATIOS[RATIOS.len() - 1]);
    Scale {
        color: diverging,
        lo: -r.ln(),
        hi: r.ln(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_equal_density_is_uniform_on_the_input() {
        let logs = log_densities(&[0.2, 0.7, 0.1], &[0.2, 0.7, 0.1]);
        let (s, uniform) = input_scale(&logs);
        assert!(uniform && s.lo == s.hi && s.lo.abs() < 1e-12);
        let (s, uniform) = input_scale(&log_densities(&[1.0, 3.0], &[1.0, 1.0]));
        assert!(!uniform && s.lo < 0.0 && s.hi > 0.0);
    }

    #[test]
    fn the_residual_scale_is_symmetric_and_round() {
        let s = residual_scale(&[0.03f64.ln_1p(), (-0.01f64).ln_1p()]);
        assert!((s.hi - 1.05f64.ln()).abs() < 1e-12 && s.lo == -s.hi);
        // A perfect map still gets a 1 % scale; a wild one the widest.
        assert!((residual_scale(&[0.0; 4]).hi - 1.01f64.ln()).abs() < 1e-12);
        assert!((residual_scale(&[-30.0, 30.0]).hi - 1e4f64.ln()).abs() < 1e-9);
        // Blue below 1, near-white at 1, red above.
        let c = colors(&s, &[-0.04, 0.0, 0.04]);
        assert!(c[0][2] > c[0][0] && c[2][0] > c[2][2], "{c:?}");
        assert!(c[1].iter().all(|&v| v > 240), "{c:?}");
    }
}
