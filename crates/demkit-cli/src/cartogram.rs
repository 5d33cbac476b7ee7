//! `demkit cartogram`: GeoJSON regions resized so that each region's area follows a value (in
//! the plane, the diffusion flow of Gastner, Seguy & More 2018; with `--sphere`, the same flow
//! in an equal-area projection of the globe; with `--project`, longitude/latitude projected to
//! Equal Earth first). Values come from a feature property or a CSV table joined on a key.
//! Exit 0 only when every region with at least 1e-4 of the total value is within the accuracy
//! asked for (`--max-error`, 1 % of its share by default) and every output polygon is valid,
//! 3 otherwise, with the reason in the report's notes.

use crate::Failure;
use crate::args::{CartogramArgs, CartogramColor};
use crate::progress::Bar;
use demkit::apps::cartogram::colours::{self, ColourBy};
use demkit::apps::cartogram::values::ValueSource;
use demkit::apps::cartogram::{
    self, Cartogram, Config, Positions, geojson, planar, project, svg, validity,
};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// One region in the report.
#[derive(Serialize)]
struct RegionEntry {
    feature: String,
    value: f64,
    input_area: f64,
    output_area: f64,
    target_share: f64,
    output_share: f64,
    error: f64,
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
    invalid_polygons: usize,
    max_error: f64,
    error_mean: f64,
    error_max: f64,
    error_max_region: String,
    grid: [usize; 2],
    regions: Vec<RegionEntry>,
    notes: Vec<String>,
}

#[derive(Serialize)]
struct MeshSummary {
    vertices: usize,
    faces: usize,
}

/// At most this many invalid polygons are named in the notes.
const NAMED_INVALID: usize = 5;

/// Refuses, before any work, what the options alone show to be wrong: output names, picture
/// size, iteration limit, accuracy, time limit and grid.
fn check_options(a: &CartogramArgs) -> Result<(), Failure> {
    crate::require_extension(
        &a.out,
        &["geojson", "json"],
        "the cartogram is written as .geojson",
    )?;
    if let Some(svg) = &a.svg {
        crate::require_extension(svg, &["svg"], "--svg writes .svg files")?;
    }
    if let Some(png) = &a.png {
        crate::render::check_png_extension(png)?;
    }
    // Checked whether or not a picture is asked for, like every other value.
    crate::render::check_size(a.size)?;
    if a.max_iter == Some(0) {
        return Err(Failure::input("--max-iter must be at least 1"));
    }
    if !(a.max_error > 0.0 && a.max_error <= 1.0) {
        return Err(Failure::input(format!(
            "--max-error must be a relative error above 0 and at most 1 (0.01 for 1 %), got {}",
            a.max_error
        )));
    }
    if let Some(t) = a.time_limit
        && !(t.is_finite() && t >= 0.0)
    {
        return Err(Failure::input(format!(
            "--time-limit must be a number of seconds, 0 or more, got {t}"
        )));
    }
    planar::check_grid(a.grid)?;
    Ok(())
}

/// Runs the cartogram command; returns the exit code (0; 3 when the accuracy asked for is not
/// met or an output polygon is invalid).
pub fn run(a: &CartogramArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    check_options(a)?;
    crate::paths::check(
        &crate::paths::given(&[
            ("REGIONS", Some(&a.regions)),
            ("--values", a.values.as_ref()),
        ]),
        &crate::paths::given(&[
            ("--out", Some(&a.out)),
            ("--svg", a.svg.as_ref()),
            ("--png", a.png.as_ref()),
            ("--report", a.report.as_ref()),
        ]),
    )?;
    let source = match (&a.values, &a.key, &a.value) {
        (Some(path), Some(key), column) => ValueSource::Table {
            path,
            key,
            column: column.as_deref(),
        },
        (None, _, Some(field)) => ValueSource::Property(field),
        _ => {
            return Err(Failure::input(
                "give the values: --value FIELD, or --values FILE.csv --key NAME",
            ));
        }
    };
    let positions = if a.sphere {
        Positions::Sphere
    } else if a.project {
        Positions::Project
    } else {
        Positions::Plane
    };
    let (fc, set) = cartogram::load(&a.regions, &source, positions)?;
    let config = Config {
        max_iter: a.max_iter,
        tolerance: a.max_error,
        grid: a.grid,
        time_limit: a.time_limit,
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
    let mut c = result?;
    // Notes of the run proper; the reading's warnings and the verdict are printed as such.
    let printed_from = c.run.notes.len();
    let warn = |c: &mut Cartogram, w: String| {
        if !a.quiet {
            eprintln!("warning: {w}");
        }
        c.run.notes.push(w);
    };
    for w in &set.warnings {
        warn(&mut c, w.clone());
    }
    if positions == Positions::Plane && looks_like_degrees(&set) {
        warn(
            &mut c,
            "the coordinates look like longitude/latitude degrees (all |x| <= 180, |y| <= 90): \
             the planar cartogram treats them as plane coordinates; use --project (Equal Earth) \
             or --sphere"
                .to_string(),
        );
    }
    if a.output_lonlat {
        c.coordinates = cartogram::degrees::to_degrees(&c.coordinates, project::inverse);
    }
    let labels: Vec<String> = c.regions.iter().map(|r| r.label.clone()).collect();
    let invalid = validity::check(&c.coordinates, &labels);
    if !invalid.is_empty() {
        let named: Vec<&str> = invalid
            .iter()
            .take(NAMED_INVALID)
            .map(|i| i.reason.as_str())
            .collect();
        warn(
            &mut c,
            format!(
                "{} output polygons are invalid: {}{}",
                invalid.len(),
                named.join("; "),
                if invalid.len() > NAMED_INVALID {
                    "; ..."
                } else {
                    ""
                }
            ),
        );
    }
    let converged = c.max_error <= config.tolerance;
    if !converged {
        let w = format!(
            "not converged: the worst region, {}, is {:.2}% off its share (asked: within \
                 {:.2}%)",
            c.max_error_region,
            100.0 * c.max_error,
            100.0 * config.tolerance
        );
        warn(&mut c, w);
    }
    let out = geojson::replace_coordinates(&fc, &c.coordinates);
    write(&a.out, geojson::to_text(out))?;
    if a.svg.is_some() || a.png.is_some() {
        let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
        let areas: Vec<f64> = c.regions.iter().map(|r| r.input_area).collect();
        let errors: Vec<f64> = c.regions.iter().map(|r| r.error).collect();
        let by = match a.color {
            CartogramColor::Density => ColourBy::Density,
            CartogramColor::Error => ColourBy::Error,
        };
        let colouring = colours::colour(by, &values, &areas, &errors);
        if let Some(path) = &a.svg {
            write(path, svg::render(&c.coordinates, &colouring))?;
        }
        if let Some(path) = &a.png {
            crate::cartogram_png::write(path, &c.coordinates, &colouring, a.size as usize)?;
        }
    }
    if let Some(path) = &a.report {
        let report = report(
            &c,
            a.sphere,
            converged,
            config.tolerance,
            invalid.len(),
            t0.elapsed().as_secs_f64(),
        );
        crate::report::write_json(path, &report)?;
    }
    if !a.quiet {
        for n in &c.run.notes[..printed_from] {
            eprintln!("note: {n}");
        }
        eprintln!(
            "cartogram: {} regions, {} steps in {} rounds ({}), share error mean {:.3}% max \
             {:.3}% ({}), {:.2} s",
            c.regions.len(),
            c.run.iterations,
            c.run.rounds,
            c.run.stop_reason.as_str(),
            100.0 * c.mean_error,
            100.0 * c.max_error,
            c.max_error_region,
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
    Ok(if converged && invalid.is_empty() {
        0
    } else {
        3
    })
}

/// Whether every position lies within ±180 × ±90, as longitude/latitude degrees do.
fn looks_like_degrees(set: &demkit::apps::cartogram::regions::RegionSet) -> bool {
    set.input_points()
        .iter()
        .all(|p| p[0].abs() <= 180.0 && p[1].abs() <= 90.0)
}

fn report(
    c: &Cartogram,
    sphere: bool,
    converged: bool,
    max_error: f64,
    invalid_polygons: usize,
    total: f64,
) -> Report {
    Report {
        method: if sphere { "flow_sphere" } else { "flow" },
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
        invalid_polygons,
        max_error,
        error_mean: c.mean_error,
        error_max: c.max_error,
        error_max_region: c.max_error_region.clone(),
        grid: c.run.grid,
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
                error: r.error,
            })
            .collect(),
        notes: c.run.notes.clone(),
    }
}

fn write(path: &Path, text: String) -> Result<(), Failure> {
    demkit::io::write_bytes_atomically(path, text.as_bytes())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))
}
