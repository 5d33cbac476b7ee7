//! `demkit register`: one genus-0 surface carried onto another through landmark-matched
//! spherical density-equalizing maps (SDEM paper §5.1).

use crate::Failure;
use crate::args::RegisterArgs;
use crate::map::check_output_extension;
use crate::progress::Bar;
use crate::surface::read_valid_mesh;
use demkit::TriMesh;
use demkit::apps::register::{register, registration_config};
use demkit::geometry::{bounding_box_diagonal, face_areas, norm, sub};
use demkit::methods::{MapResult, lsdem};
use demkit::metrics::{Domain, map_areas};
use serde::Serialize;
use std::time::Instant;

/// What `--report` holds for a registration.
#[derive(Serialize)]
struct RegisterReport {
    method: &'static str,
    vertices_a: usize,
    vertices_b: usize,
    landmarks: usize,
    /// Mean |f(p_i) − g(q_i)| of the two spherical maps at the landmark pairs.
    landmark_mismatch_sphere: f64,
    /// Mean distance between A's landmarks carried onto B and B's landmarks, in B's units.
    landmark_error: f64,
    /// The same divided by B's bounding-box diagonal.
    landmark_error_relative: f64,
    map_a: MapSummary,
    map_b: MapSummary,
    time_s: f64,
}

/// One of the two spherical maps.
#[derive(Serialize)]
struct MapSummary {
    converged: bool,
    stop_reason: &'static str,
    iterations: usize,
    flipped_triangles: usize,
}

impl MapSummary {
    fn new(r: &MapResult, faces: &[[u32; 3]]) -> Self {
        MapSummary {
            converged: r.converged,
            stop_reason: r.stop_reason.as_str(),
            iterations: r.iterations,
            flipped_triangles: map_areas(&r.positions, faces, Domain::Sphere).1,
        }
    }
}

/// Runs the register command; returns the exit code (0; 3 if a map did not converge; 1 if a
/// spherical map has flipped triangles — the result is still written).
pub fn run(a: &RegisterArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    check_output_extension(&a.out)?;
    // The weights and the stop in the ranges every map's options have.
    demkit::options::check_values(&demkit::MapOptions {
        alpha: a.weights.alpha,
        beta: a.weights.beta,
        gamma: a.weights.gamma,
        epsilon: a.stop.epsilon,
        max_iter: a.stop.max_iter,
        ..demkit::MapOptions::default()
    })?;
    crate::paths::check(
        &crate::paths::given(&[
            ("A", Some(&a.a)),
            ("B", Some(&a.b)),
            ("--landmarks-a", Some(&a.landmarks_a)),
            ("--landmarks-b", Some(&a.landmarks_b)),
        ]),
        &crate::paths::given(&[("--out", Some(&a.out)), ("--report", a.report.as_ref())]),
    )?;
    let surface_a = read_valid_mesh(&a.a, a.quiet)?;
    let surface_b = read_valid_mesh(&a.b, a.quiet)?;
    let (mesh_a, mesh_b) = (surface_a.mesh(), surface_b.mesh());
    let exponent_b = surface_b.exponent();
    let la = demkit::io::landmarks::read_landmark_vertices(&a.landmarks_a, mesh_a.n_vertices())?;
    let lb = demkit::io::landmarks::read_landmark_vertices(&a.landmarks_b, mesh_b.n_vertices())?;
    if la.len() != lb.len() {
        return Err(Failure::input(format!(
            "--landmarks-a has {} landmarks and --landmarks-b has {}; they must correspond line by line",
            la.len(),
            lb.len()
        )));
    }
    let pairs: Vec<(usize, usize)> = la.iter().copied().zip(lb.iter().copied()).collect();
    let pop_a = face_areas(&mesh_a.positions, &mesh_a.faces);
    let pop_b = face_areas(&mesh_b.positions, &mesh_b.faces);
    let bar = Bar::new(a.quiet, "register");
    let mut progress = |p| bar.update(p);
    let reg = register(
        mesh_a,
        mesh_b,
        &pairs,
        &pop_a,
        &pop_b,
        &config(a),
        &mut progress,
    );
    bar.finish();
    let reg = reg?;
    // On B's surface, in B's units.
    let mut on_b = TriMesh::new(reg.positions.clone(), mesh_a.faces.clone());
    demkit::mesh::scale::scale_positions(&mut on_b.positions, -exponent_b);
    demkit::io::write_mesh(&a.out, &on_b)?;

    let diagonal = bounding_box_diagonal(&mesh_b.positions);
    let landmark_error = pairs
        .iter()
        .map(|&(p, q)| norm(sub(reg.positions[p], mesh_b.positions[q])))
        .sum::<f64>()
        / pairs.len() as f64;
    let summary_a = MapSummary::new(&reg.map_a, &mesh_a.faces);
    let summary_b = MapSummary::new(&reg.map_b, &mesh_b.faces);
    let flipped = summary_a.flipped_triangles + summary_b.flipped_triangles;
    let converged = summary_a.converged && summary_b.converged;
    if let Some(path) = &a.report {
        let report = RegisterReport {
            method: "register",
            vertices_a: mesh_a.n_vertices(),
            vertices_b: mesh_b.n_vertices(),
            landmarks: pairs.len(),
            landmark_mismatch_sphere: reg.landmark_mismatch,
            landmark_error,
            landmark_error_relative: landmark_error / diagonal,
            map_a: summary_a,
            map_b: summary_b,
            time_s: t0.elapsed().as_secs_f64(),
        };
        crate::report::write_json(path, &report)?;
    }
    if !a.quiet {
        eprintln!(
            "register: {} landmark pairs, landmark distance on B {:.3e} ({:.2}% of the diagonal), {:.2} s",
            pairs.len(),
            landmark_error,
            100.0 * landmark_error / diagonal,
            t0.elapsed().as_secs_f64()
        );
    }
    if flipped > 0 {
        eprintln!("error: the spherical maps have {flipped} flipped triangles");
        return Ok(1);
    }
    Ok(if converged { 0 } else { 3 })
}

/// LSDEM's configuration for registration, with the settings given on the command line.
fn config(a: &RegisterArgs) -> lsdem::Config {
    let mut c = registration_config();
    c.alpha = a.weights.alpha.unwrap_or(c.alpha);
    c.beta = a.weights.beta.unwrap_or(c.beta);
    c.gamma = a.weights.gamma.unwrap_or(c.gamma);
    c.max_iter = a.stop.max_iter.unwrap_or(c.max_iter);
    c.epsilon = a.stop.epsilon.unwrap_or(c.epsilon);
    c
}
