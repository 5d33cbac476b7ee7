//! `demkit remesh`: a new triangulation of the input surface laid out through its
//! density-equalizing map (DEM paper §6.2, SDEM paper §5.2, DEQ paper §7.1): uniform points on
//! the map's domain, triangulated there and pulled back onto the surface, so that the vertex
//! density follows the population.

use crate::Failure;
use crate::args::RemeshArgs;
use crate::map::{check_output_extension, compute, resolve_method, warn_unused};
use crate::surface::read_valid_mesh;
use demkit::Method;
use demkit::apps::remesh::quality::{max_distance_to_surface, quality};
use demkit::apps::remesh::{Target, check_vertex_count, min_vertices, remesh};
use demkit::mesh::topology::topology;
use demkit::report::InputSummary;
use serde::Serialize;
use std::time::Instant;

/// Above this mean |log(area share / population share)| the map is said to equalize the density
/// only roughly.
const DENSITY_ERROR_WARNING: f64 = 0.25;

/// The report of `demkit remesh --report`.
#[derive(Serialize)]
struct RemeshReport {
    method: String,
    population: String,
    converged: bool,
    input: InputSummary,
    output: InputSummary,
    map: MapFigures,
    quality: QualityFigures,
    time_s: Times,
}

/// The figures of the map the remeshing went through.
#[derive(Serialize)]
struct MapFigures {
    iterations: usize,
    flipped_triangles: usize,
    density_error_mean: f64,
}

/// The figures of the new mesh.
#[derive(Serialize)]
struct QualityFigures {
    area_cv: f64,
    median_min_angle_deg: f64,
    min_angle_deg: f64,
    /// The largest distance of a new vertex from the input surface over the input's
    /// bounding-box diagonal.
    max_distance_over_diagonal: f64,
}

/// Timings in seconds.
#[derive(Serialize)]
struct Times {
    map: f64,
    remesh: f64,
    total: f64,
}

/// Runs the remesh command; returns the exit code (0, 1 when the map has flipped triangles, 3
/// when the map did not converge — the mesh and the report are still written).
pub fn run(a: &RemeshArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    check_output_extension(&a.out)?;
    crate::map::check_values(&a.m)?;
    let (population, landmarks) = crate::paths::method_inputs(&a.m);
    crate::paths::check(
        &crate::paths::mesh_inputs(&a.mesh, &population, &landmarks),
        &crate::paths::given(&[("--out", Some(&a.out)), ("--report", a.report.as_ref())]),
    )?;
    let surface = read_valid_mesh(&a.mesh, a.quiet)?;
    let (mesh, exponent) = (surface.mesh(), surface.exponent());
    let topo = surface.topology();
    let method = resolve_method(&a.m, topo.boundary_loops.len(), topo.genus)?;
    warn_unused(&a.m, method, a.quiet);
    check_vertex_count(a.vertices)?;
    let least = min_vertices(topo.boundary_loops.len(), topo.genus);
    if a.vertices < least {
        return Err(Failure::input(format!(
            "--vertices must be at least {least} for a surface with {} boundary loops and genus {}, got {}",
            topo.boundary_loops.len(),
            topo.genus,
            a.vertices
        )));
    }

    // The vertex spacing follows the map's density: DEQ puts it first unless told otherwise.
    let mut m = a.m.clone();
    if matches!(method, Method::Deq | Method::Ldeq) && m.weights.alpha.is_none() {
        m.weights.alpha = Some(demkit::apps::remesh::DEQ_ALPHA);
    }
    let c = compute(&surface, method, &m, a.quiet)?;
    let metrics = &c.map.metrics;
    let result = &c.map.result;
    let t_map = t0.elapsed().as_secs_f64();
    if metrics.flipped_triangles > 0 {
        eprintln!(
            "error: the {} map has {} flipped triangles; the inverse map is not defined there, so the surface cannot be remeshed through it",
            method.name(),
            metrics.flipped_triangles
        );
        return Ok(1);
    }
    let target = match (&result.flat_torus, &c.torus, result.ellipsoid) {
        (Some(map), Some(torus), _) => Target::Torus { map, torus },
        (_, _, Some(e)) => Target::Ellipsoid(e),
        _ if method.maps_onto_sphere() => Target::Sphere,
        _ => Target::Plane,
    };
    // A planar layout makes up for a map's residual density; the sphere and the torus do not.
    if !a.quiet
        && !matches!(target, Target::Plane)
        && metrics.density_error_mean > DENSITY_ERROR_WARNING
    {
        eprintln!(
            "warning: the {} map equalizes the density only roughly (density error {:.2}); the new mesh's vertex density follows the map, so it follows the population only as well",
            method.name(),
            metrics.density_error_mean
        );
    }
    let t1 = Instant::now();
    let out = remesh(
        c.mesh(),
        &c.map.population,
        &result.positions,
        target,
        a.vertices,
    )?;
    let t_remesh = t1.elapsed().as_secs_f64();
    let mut unscaled = out.clone();
    demkit::mesh::scale::scale_positions(&mut unscaled.positions, -exponent);
    demkit::io::write_mesh(&a.out, &unscaled)?;

    let q = quality(&out);
    let out_topo = topology(&out);
    if let Some(path) = &a.report {
        let diagonal = demkit::geometry::bounding_box_diagonal(&mesh.positions);
        let report = RemeshReport {
            method: c.method.name().to_string(),
            population: a.m.population.clone(),
            converged: result.converged,
            input: InputSummary::of_surface(&surface),
            output: InputSummary {
                vertices: out.n_vertices(),
                faces: out.n_faces(),
                boundaries: out_topo.boundary_loops.len(),
                genus: out_topo.genus,
            },
            map: MapFigures {
                iterations: result.iterations,
                flipped_triangles: metrics.flipped_triangles,
                density_error_mean: metrics.density_error_mean,
            },
            quality: QualityFigures {
                area_cv: q.area_cv,
                median_min_angle_deg: q.median_min_angle_deg,
                min_angle_deg: q.min_angle_deg,
                max_distance_over_diagonal: max_distance_to_surface(
                    &out.positions,
                    mesh,
                    1e-6 * diagonal,
                ) / diagonal,
            },
            time_s: Times {
                map: t_map,
                remesh: t_remesh,
                total: t0.elapsed().as_secs_f64(),
            },
        };
        let text = serde_json::to_string_pretty(&report).map_err(|e| Failure {
            code: 1,
            message: e.to_string(),
        })?;
        demkit::io::write_bytes_atomically(path, (text + "\n").as_bytes())
            .map_err(|e| Failure::input(format!("{}: {e}", path.display())))?;
    }
    if !a.quiet {
        for n in &result.notes {
            eprintln!("note: {n}");
        }
        eprintln!(
            "remesh ({}): {} vertices, {} faces, {} boundary loops, genus {}; area CV {:.3}, median smallest angle {:.1}°, {:.2} s",
            method.name(),
            out.n_vertices(),
            out.n_faces(),
            out_topo.boundary_loops.len(),
            out_topo.genus,
            q.area_cv,
            q.median_min_angle_deg,
            t0.elapsed().as_secs_f64()
        );
    }
    Ok(if result.converged { 0 } else { 3 })
}
