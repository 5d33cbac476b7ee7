//! `demkit cartogram`: GeoJSON regions resized so that each region's area follows a value
//! (DEM paper §6.1; with `--sphere`, SDEM paper §5.3).

use crate::Failure;
use crate::args::CartogramArgs;
use crate::progress::Bar;
use demkit::apps::cartogram::{self, Cartogram, Config, geojson, planar, svg};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// A worst area/value error above this is worth a warning.
const WARN_ERROR: f64 = 0.05;

/// One region in the report.
#[derive(Serialize)]
struct RegionEntry {
    feature: String,
    value: f64,
    input_area: f64,
    output_area: f64,
    target_share: f64,
    output_share: f64,
    ratio_error: f64,
}

/// The report of `demkit cartogram --report`.
#[derive(Serialize)]
struct Report {
    method: &'static str,
    features: usize,
    mesh: MeshSummary,
    converged: bool,
    stop_reason: &'static str,
    iterations: usize,
    rounds: usize,
    time_s: f64,
    flipped_triangles: usize,
    ratio_error_median: f64,
    ratio_error_worst: f64,
    regions: Vec<RegionEntry>,
    notes: Vec<String>,
}

#[derive(Serialize)]
struct MeshSummary {
    vertices: usize,
    faces: usize,
}

/// Runs the cartogram command; returns the exit code (0, or 3 when not converged).
pub fn run(a: &CartogramArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    crate::require_extension(
        &a.out,
        &["geojson", "json"],
        "the cartogram is written as .geojson",
    )?;
    if let Some(svg) = &a.svg {
        crate::require_extension(svg, &["svg"], "--svg writes .svg files")?;
    }
    if a.max_iter == Some(0) {
        return Err(Failure::input("--max-iter must be at least 1"));
    }
    if let Some(n) = a.faces {
        cartogram::check_max_faces(n)?;
    }
    crate::paths::check(
        &crate::paths::given(&[("REGIONS", Some(&a.regions))]),
        &crate::paths::given(&[
            ("--out", Some(&a.out)),
            ("--svg", a.svg.as_ref()),
            ("--report", a.report.as_ref()),
        ]),
    )?;
    let (fc, set) = cartogram::load(&a.regions, &a.value, a.sphere)?;
    let config = Config {
        max_iter: a.max_iter,
        max_faces: a.faces.unwrap_or(cartogram::DEFAULT_MAX_FACES),
        ..Config::default()
    };
    let label = a.regions.display().to_string();
    let bar = Bar::new(a.quiet, "cartogram");
    let result = if a.sphere {
        cartogram::sphere::run(&set, &config, &label, &mut |p| bar.update(p))
    } else {
        planar::run(&set, &config, &label, &mut |p| bar.update(p))
    };
    bar.finish();
    let c = result?;
    let out = geojson::replace_coordinates(&fc, &c.coordinates);
    write(&a.out, geojson::to_text(out))?;
    if let Some(path) = &a.svg {
        let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
        write(path, svg::render(&c.coordinates, &values))?;
    }
    let converged = c.run.stop_reason != demkit::methods::StopReason::MaxIter;
    if let Some(path) = &a.report {
        let report = report(&c, a.sphere, converged, t0.elapsed().as_secs_f64());
        crate::report::write_json(path, &report)?;
    }
    if !a.quiet {
        for n in &c.run.notes {
            eprintln!("note: {n}");
        }
        if c.worst_error > WARN_ERROR {
            eprintln!(
                "warning: the worst region's area/value is {:.1}% off the mean ratio (see --report)",
                100.0 * c.worst_error
            );
        }
        eprintln!(
            "cartogram: {} regions, {} iterations in {} rounds ({}), area/value error median {:.4} worst {:.4}, {:.2} s",
            c.regions.len(),
            c.run.iterations,
            c.run.rounds,
            c.run.stop_reason.as_str(),
            c.median_error,
            c.worst_error,
            t0.elapsed().as_secs_f64()
        );
    }
    if c.run.flipped_triangles > 0 {
        eprintln!(
            "error: the map has {} flipped triangles",
            c.run.flipped_triangles
        );
        return Ok(1);
    }
    Ok(if converged { 0 } else { 3 })
}

fn report(c: &Cartogram, sphere: bool, converged: bool, total: f64) -> Report {
    Report {
        method: if sphere { "sdem" } else { "dem" },
        features: c.regions.len(),
        mesh: MeshSummary {
            vertices: c.run.mesh_vertices,
            faces: c.run.mesh_faces,
        },
        converged,
        stop_reason: c.run.stop_reason.as_str(),
        iterations: c.run.iterations,
        rounds: c.run.rounds,
        time_s: total,
        flipped_triangles: c.run.flipped_triangles,
        ratio_error_median: c.median_error,
        ratio_error_worst: c.worst_error,
        regions: c
            .regions
            .iter()
            .map(|r| RegionEntry {
                feature: r.label.clone(),
                value: r.value,
                input_area: r.input_area,
                output_area: r.output_area,
                target_share: r.target_share,
                output_share: r.output_share,
                ratio_error: r.ratio_error,
            })
            .collect(),
        notes: c.run.notes.clone(),
    }
}

fn write(path: &Path, text: String) -> Result<(), Failure> {
    demkit::io::write_bytes_atomically(path, text.as_bytes())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))
}
