//! Pictures: `demkit render`, and `map --render` / `map --histogram`.
//!
//! Meshes are drawn by a small z-buffered rasterizer ([`raster`]) through an orthographic
//! camera ([`camera`]): planar meshes flat from above, surfaces in space lit from a chosen view;
//! faces are coloured with viridis or a diverging map ([`colormap`]). `map --render` puts the
//! input and the map side by side ([`figure`], [`residual`]) with colour bars ([`colorbar`])
//! and a checkerboard carried from the initial map ([`checker`]). The histograms follow the
//! papers' figures ([`histogram`], [`plot`]).

mod camera;
mod checker;
mod colorbar;
mod colormap;
mod figure;
pub(crate) mod font;
mod histogram;
mod plot;
mod raster;
mod residual;
mod scene;
mod ticks;

use crate::Failure;
use crate::args::{MapArgs, RenderArgs};
use camera::View;
use demkit::metrics::map_areas;
use demkit::{Map, TriMesh};
use raster::Rgb;
use std::path::Path;
use tiny_skia::Pixmap;

/// The colour of faces when `render` is given no values.
const PLAIN: Rgb = [176, 190, 212];

/// Pictures are written as .png only.
pub fn check_png_extension(path: &Path) -> Result<(), Failure> {
    crate::require_extension(path, &["png"], "pictures are written as .png")
}

/// Checks `map`'s picture options before the map is computed: .png names, `--view`, `--size`
/// (their values whether or not a picture is asked for). A `--view` with no picture to draw
/// is named in a warning unless `quiet`.
pub fn check_map_args(a: &MapArgs, quiet: bool) -> Result<(), Failure> {
    for png in [&a.render, &a.histogram].into_iter().flatten() {
        check_png_extension(png)?;
    }
    parse_view(a.picture.view.as_deref())?;
    check_size(a.picture.size)?;
    if a.render.is_none() && a.histogram.is_none() && a.picture.view.is_some() && !quiet {
        eprintln!("warning: --view not used without --render or --histogram");
    }
    Ok(())
}

/// Draws the input surface and the map side by side ([`residual::figure`]): the input
/// coloured by its population density, the map by the density left after the map, both with
/// a checkerboard carried from the initial map.
pub fn render_map(png: &Path, mesh: &TriMesh, map: &Map, a: &MapArgs) -> Result<(), Failure> {
    let size = check_size(a.picture.size)?;
    let view = parse_view(a.picture.view.as_deref())?;
    write_png(png, residual::figure(mesh, map, view, size))
}

/// Draws the histograms of the face density P(T)/A(T) over its mean on the initial and on the
/// final map side by side, as in the papers' figures.
pub fn render_histograms(
    png: &Path,
    mesh: &TriMesh,
    map: &Map,
    a: &MapArgs,
) -> Result<(), Failure> {
    let size = check_size(a.picture.size)?;
    let (initial, _) = map_areas(&map.result.initial, &mesh.faces, map.metrics_domain());
    let (last, _) = map_areas(&map.result.positions, &mesh.faces, map.metrics_domain());
    let d0 = histogram::normalized_densities(&map.population, &initial);
    let d1 = histogram::normalized_densities(&map.population, &last);
    write_png(png, plot::histograms(&d0, &d1, size))
}

/// Runs the render command; returns the exit code.
pub fn run(a: &RenderArgs) -> Result<u8, Failure> {
    check_png_extension(&a.out)?;
    let view = parse_view(a.picture.view.as_deref())?;
    let size = check_size(a.picture.size)?;
    crate::paths::check(
        &crate::paths::given(&[("MESH", Some(&a.mesh)), ("--color", a.color.as_ref())]),
        &crate::paths::given(&[("--out", Some(&a.out))]),
    )?;
    let surface = crate::surface::read_valid_mesh(&a.mesh, a.quiet)?;
    let mesh = surface.mesh();
    let colors = match &a.color {
        Some(path) => value_colors(&read_face_values(path, mesh.n_faces())?),
        None => vec![PLAIN; mesh.n_faces()],
    };
    let style = scene_style(&mesh.positions, view, size);
    write_png(
        &a.out,
        scene::draw(&mesh.positions, &mesh.faces, &colors, style, None),
    )?;
    Ok(0)
}

/// One finite value per face from a file in the population-file format.
fn read_face_values(path: &Path, n_faces: usize) -> Result<Vec<f64>, Failure> {
    let values =
        demkit::population::read_face_values(path, n_faces, "colour file").map_err(|e| {
            let f = Failure::from(e);
            Failure {
                message: format!("--color: {}", f.message),
                ..f
            }
        })?;
    if let Some((f, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Failure::input(format!(
            "--color file {}: the value of face {f} is {v}",
            path.display()
        )));
    }
    Ok(values)
}

/// Viridis colours of values, spread between their 0.5 % and 99.5 % quantiles.
fn value_colors(values: &[f64]) -> Vec<Rgb> {
    colormap::normalize(values)
        .into_iter()
        .map(colormap::viridis)
        .collect()
}

/// How a mesh is drawn: from `view` when given, else from its default view ([`default_view`]);
/// lit unless planar; `size` × `size` pixels.
fn scene_style(positions: &[[f64; 3]], view: Option<View>, size: usize) -> scene::Style {
    let planar = is_planar(positions);
    scene::Style::square(
        view.unwrap_or_else(|| default_view(positions, planar)),
        !planar,
        size,
    )
}

/// All z equal (up to rounding against the extent in x and y).
fn is_planar(positions: &[[f64; 3]]) -> bool {
    let e = extents(positions);
    e[2] <= 1e-12 * e[0].max(e[1])
}

/// The default view: from above for planar meshes; steeply from the front for surfaces
/// flattest along z (height fields, tori around the z-axis); obliquely otherwise.
fn default_view(positions: &[[f64; 3]], planar: bool) -> View {
    let e = extents(positions);
    if planar {
        View::TOP
    } else if e[2] < 0.9 * e[0].min(e[1]) {
        View::HIGH
    } else {
        View::OBLIQUE
    }
}

/// The extent of the finite points along x, y and z.
fn extents(positions: &[[f64; 3]]) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions.iter().filter(|p| p.iter().all(|c| c.is_finite())) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    std::array::from_fn(|k| (hi[k] - lo[k]).max(0.0))
}

/// `--view` when given.
fn parse_view(s: Option<&str>) -> Result<Option<View>, Failure> {
    s.map(View::parse).transpose().map_err(Failure::input)
}

/// Picture sizes from 64 to 4096 pixels.
pub(crate) fn check_size(size: i64) -> Result<usize, Failure> {
    if (64..=4096).contains(&size) {
        Ok(size as usize)
    } else {
        Err(Failure::input(format!(
            "--size must be from 64 to 4096 pixels, got {size}"
        )))
    }
}

/// Encodes and writes a picture; an unwritable path is an input error naming it.
pub(crate) fn write_png(path: &Path, pixmap: Option<Pixmap>) -> Result<(), Failure> {
    let internal = |m: String| Failure {
        code: 1,
        message: format!("cannot draw '{}': {m}", path.display()),
    };
    let pixmap = pixmap.ok_or_else(|| internal("no picture".into()))?;
    let bytes = pixmap.encode_png().map_err(|e| internal(e.to_string()))?;
    demkit::io::write_bytes_atomically(path, &bytes)
        .map_err(|e| Failure::input(format!("cannot write '{}': {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planarity_and_default_views() {
        let flat = [[0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 3.0, 1.0]];
        assert!(is_planar(&flat));
        assert_eq!(default_view(&flat, true), View::TOP);
        let bump = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.5]];
        assert!(!is_planar(&bump));
        assert_eq!(default_view(&bump, false), View::HIGH);
        let tall = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 3.0]];
        assert_eq!(default_view(&tall, false), View::OBLIQUE);
    }

    #[test]
    fn size_limits() {
        assert!(check_size(64).is_ok() && check_size(4096).is_ok());
        for bad in [0, 63, 4097] {
            let e = check_size(bad).err().map(|f| (f.code, f.message));
            assert_eq!(
                e,
                Some((
                    2,
                    format!("--size must be from 64 to 4096 pixels, got {bad}")
                ))
            );
        }
    }
}
