//! `demkit cartogram`: GeoJSON regions resized so that each region's area follows a value (in
//! the plane, the diffusion flow of Gastner, Seguy & More 2018; with `--sphere`, the same flow
//! in an equal-area projection of the globe). Exit 0 only when every region with at least 1e-4 of the total value is within the
//! accuracy asked for (1 % of its share), 3 otherwise, with the reason in the report's notes.

use crate::Failure;
use crate::args::CartogramArgs;
use crate::progress::Bar;
use demkit::apps::cartogram::{self, Cartogram, Config, geojson, planar, svg};
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
    ratio_error: f64,
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
    ratio_error_median: f64,
    ratio_error_worst: f64,
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
    let mut c = result?;
    // Notes of the run proper; the reading's warnings and the verdict are printed as such.
    let printed_from = c.run.notes.len();
    for w in &set.warnings {
        if !a.quiet {
            eprintln!("warning: {w}");
        }
        c.run.notes.push(w.clone());
    }
    if !a.sphere && looks_like_degrees(&set) {
        let w = "the coordinates look like longitude/latitude degrees (all |x| <= 180, |y| <= \
                 90): the planar cartogram treats them as plane coordinates; use --sphere, or \
                 project them to an equal-area projection first"
            .to_string();
        if !a.quiet {
            eprintln!("warning: {w}");
        }
        c.run.notes.push(w);
    }
    let converged = c.max_error <= config.tolerance;
    if !converged {
        c.run.notes.push(format!(
            "not converged: the worst region, {}, is {:.2}% off its share (asked: within {:.2}%)",
            c.max_error_region,
            100.0 * c.max_error,
            100.0 * config.tolerance
        ));
        if !a.quiet {
            eprintln!("warning: {}", c.run.notes[c.run.notes.len() - 1]);
        }
    }
    let out = geojson::replace_coordinates(&fc, &c.coordinates);
    write(&a.out, geojson::to_text(out))?;
    if let Some(path) = &a.svg {
        let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
        write(path, svg::render(&c.coordinates, &values))?;
    }
    if let Some(path) = &a.report {
        let report = report(
            &c,
            a.sphere,
            converged,
            config.tolerance,
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
    Ok(if converged { 0 } else { 3 })
}

/// Whether every position lies within ±180 × ±90, as longitude/latitude degrees do.
fn looks_like_degrees(set: &demkit::apps::cartogram::regions::RegionSet) -> bool {
    set.input_points()
        .iter()
        .all(|p| p[0].abs() <= 180.0 && p[1].abs() <= 90.0)
}

fn report(c: &Cartogram, sphere: bool, converged: bool, max_error: f64, total: f64) -> Report {
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
        ratio_error_median: c.median_error,
        ratio_error_worst: c.worst_error,
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
                ratio_error: r.ratio_error,
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
