//! `demkit map`: read, validate, map, write the mesh and the report.

use crate::Failure;
use crate::args::{MapArgs, Method, MethodArgs};
use crate::progress::Bar;
use crate::report::{InputSummary, Report};
use demkit::TriMesh;
use demkit::geometry::torus::Torus;
use demkit::init::shape::Shape;
use demkit::mesh::topology::topology;
use demkit::methods::{
    circle_conformal, dem, dem_shape, deq, ldeq, lsdem, sdem, spherical_conformal, tdem,
};
use demkit::metrics::{Domain, compute as compute_metrics};
use demkit::population::{PopulationSpec, face_populations_at_scale};
use std::path::Path;
use std::time::Instant;

/// Only .obj and .ply are written.
pub fn check_output_extension(out: &Path) -> Result<(), Failure> {
    crate::require_extension(
        out,
        &["obj", "ply"],
        "output meshes must end in .obj or .ply",
    )
}

/// A computed map with what it was computed from.
pub struct Computed {
    /// The method that ran (never `Auto`).
    pub method: Method,
    /// The surface mapped when the method refined the input (DEQ splits the chords of holes).
    pub refined_mesh: Option<TriMesh>,
    /// The population of every face of the surface mapped.
    pub population: Vec<f64>,
    /// The landmarks, when the method uses them.
    pub landmarks: Option<Vec<(usize, [f64; 3])>>,
    /// The map.
    pub result: demkit::methods::MapResult,
    /// Where the map lies (plane, sphere, torus), for the metrics.
    pub domain: Domain,
    /// The target torus of tdem.
    pub torus: Option<Torus>,
}

impl Computed {
    /// The surface mapped: the refined one if the method refined `input`, else `input`.
    pub fn surface<'a>(&'a self, input: &'a TriMesh) -> &'a TriMesh {
        self.refined_mesh.as_ref().unwrap_or(input)
    }

    /// The report metrics of this map of `input` (DESIGN.md, "Report").
    pub fn metrics(&self, input: &TriMesh) -> demkit::metrics::Metrics {
        compute_metrics(
            self.surface(input),
            &self.population,
            &self.result.initial,
            &self.result.positions,
            self.domain,
            self.landmarks.as_deref(),
        )
    }
}

/// Computes the density-equalizing map of a validated mesh with the options of `map` and
/// `remesh`; `method` comes from [`resolve_method`].
/// `mesh` is the input scaled by 2^`exponent` ([`read_valid_mesh`]): population expressions
/// and `--torus` are in input units.
pub fn compute(
    mesh: &TriMesh,
    exponent: i32,
    method: Method,
    a: &MethodArgs,
    quiet: bool,
) -> Result<Computed, Failure> {
    let population = demkit::population::unit_scale(&face_populations_at_scale(
        &PopulationSpec::parse(&a.population),
        mesh,
        exponent,
    )?);
    let landmarks: Option<Vec<(usize, [f64; 3])>> = match &a.landmarks {
        Some(path)
            if matches!(
                method,
                Method::Lsdem | Method::Sdem | Method::SphericalConformal | Method::Ldeq
            ) =>
        {
            let l = demkit::io::landmarks::read_landmarks(path, mesh.n_vertices())?;
            Some(l.into_iter().map(|l| (l.vertex, l.target)).collect())
        }
        _ => None,
    };
    if method == Method::Lsdem && landmarks.is_none() {
        return Err(Failure::input(
            "--method lsdem needs --landmarks FILE (vertex_index x y z per line)",
        ));
    }
    if method == Method::Ldeq && landmarks.is_none() {
        return Err(Failure::input(
            "--method ldeq needs --landmarks FILE (vertex_index x y per line)",
        ));
    }
    let torus = match (&a.torus, method) {
        (Some(s), Method::Tdem) => Some(parse_torus(s)?.scaled_by_power_of_two(exponent)),
        (None, Method::Tdem) => {
            return Err(Failure::input(
                "--method tdem (for genus-one closed surfaces) needs the target torus: --torus R:r with R > r > 0",
            ));
        }
        _ => None,
    };

    let bar = Bar::new(quiet, method.name());
    let mut progress = |p| bar.update(p);
    let result = match method {
        Method::Dem => {
            let mut c = dem::Config::default();
            apply_common(&mut c.epsilon, &mut c.max_iter, &mut c.dt, a);
            dem::run(mesh, &population, &c, &mut progress)
        }
        Method::DemShape => {
            let shape = match &a.shape {
                Some(s) => Shape::parse(s)?,
                None => Shape::Disk,
            };
            let mut c = dem_shape::Config {
                shape,
                ..Default::default()
            };
            apply_common(&mut c.epsilon, &mut c.max_iter, &mut c.dt, a);
            dem_shape::run(mesh, &population, &c, &mut progress)
        }
        Method::Sdem => {
            let mut c = sdem::Config::default();
            let mut dt = Some(c.dt);
            apply_common(&mut c.epsilon, &mut c.max_iter, &mut dt, a);
            c.dt = dt.unwrap_or(c.dt);
            sdem::run(mesh, &population, &c, &mut progress)
        }
        Method::SphericalConformal => spherical_conformal::run(mesh, &population),
        Method::CircleConformal => circle_conformal::run(mesh, &population),
        Method::Deq => deq::run(mesh, &population, &deq_config(a), &mut progress),
        Method::Ldeq => {
            let c = ldeq::Config { deq: deq_config(a) };
            let l = landmarks.as_deref().unwrap_or(&[]);
            ldeq::run(mesh, &population, l, &c, &mut progress)
        }
        Method::Lsdem => {
            let mut c = lsdem::Config::default();
            let mut dt = Some(c.dt);
            apply_common(&mut c.epsilon, &mut c.max_iter, &mut dt, a);
            c.dt = dt.unwrap_or(c.dt);
            c.alpha = a.alpha.unwrap_or(c.alpha);
            c.beta = a.beta.unwrap_or(c.beta);
            c.gamma = a.gamma.unwrap_or(c.gamma);
            let l = landmarks.as_deref().unwrap_or(&[]);
            lsdem::run(mesh, &population, l, &c, &mut progress)
        }
        Method::Tdem => {
            let mut c = tdem::Config::default();
            apply_common(&mut c.epsilon, &mut c.max_iter, &mut c.dt, a);
            match torus.as_ref() {
                Some(torus) => tdem::run(mesh, &population, torus, &c, &mut progress),
                None => unreachable!("a missing --torus is refused above"),
            }
        }
        Method::Auto => {
            bar.finish();
            return Err(Failure {
                code: 1,
                message: "internal error: no method was chosen".into(),
            });
        }
    };
    bar.finish();
    let mut result = result?;
    let (population, refined_mesh) = match result.refined.take() {
        Some(r) => (r.population, Some(r.mesh)),
        None => (population, None),
    };
    let domain = match (&result.flat_torus, &torus) {
        (Some(flat), Some(t)) => Domain::Torus {
            flipped: flat.count_flipped(&mesh.faces, t.periods()),
        },
        _ => match method {
            Method::Sdem | Method::Lsdem | Method::SphericalConformal => Domain::Sphere,
            _ => Domain::Plane,
        },
    };
    Ok(Computed {
        method,
        refined_mesh,
        population,
        landmarks,
        result,
        domain,
        torus,
    })
}

/// Reads and validates a mesh, printing validation warnings unless `quiet`. A mesh far from
/// unit size is scaled by 2^k (exact, [`demkit::mesh::scale`]) and `k` returned with it:
/// results in input units are scaled back by 2^−k.
pub fn read_valid_mesh(path: &Path, quiet: bool) -> Result<(TriMesh, i32), Failure> {
    let mesh = demkit::io::read_mesh(path)?;
    let (mut mesh, warnings) = demkit::mesh::validate::validate(mesh)?;
    if !quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    let k = demkit::mesh::scale::normalizing_exponent(&mesh.positions);
    demkit::mesh::scale::scale_positions(&mut mesh.positions, k);
    Ok((mesh, k))
}

/// Runs the map command; returns the exit code (0, or 3 when not converged).
pub fn run(a: &MapArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    check_output_extension(&a.out)?;
    if let Some(uv) = &a.uv_out {
        check_uv_extension(uv)?;
    }
    crate::render::check_map_args(a)?;
    let (population, landmarks) = crate::paths::method_inputs(&a.m);
    crate::paths::check(
        &crate::paths::mesh_inputs(&a.mesh, &population, &landmarks),
        &crate::paths::given(&[
            ("--out", Some(&a.out)),
            ("--uv-out", a.uv_out.as_ref()),
            ("--render", a.render.as_ref()),
            ("--histogram", a.histogram.as_ref()),
            ("--report", a.report.as_ref()),
        ]),
    )?;
    let (input, exponent) = read_valid_mesh(&a.mesh, a.quiet)?;
    let topo = topology(&input);
    let method = resolve_method(&a.m, topo.boundary_loops.len(), topo.genus)?;
    warn_unused(&a.m, method, a.quiet);
    if a.uv_out.is_some()
        && matches!(
            method,
            Method::Sdem | Method::Lsdem | Method::SphericalConformal
        )
    {
        return Err(Failure::input(format!(
            "--uv-out needs a planar, circle-domain or torus map, and --method {} maps onto the sphere",
            method.name()
        )));
    }
    let mut c = compute(&input, exponent, method, &a.m, a.quiet)?;
    let metrics = c.metrics(&input);
    c.result.judge(&metrics, a.m.dt);
    let result = &c.result;
    let mesh = c.surface(&input);
    let mut out_mesh = TriMesh::new(result.positions.clone(), mesh.faces.clone());
    if c.torus.is_some() {
        // On the target torus, in input units.
        demkit::mesh::scale::scale_positions(&mut out_mesh.positions, -exponent);
    }
    demkit::io::write_mesh(&a.out, &out_mesh)?;
    if let Some(uv) = &a.uv_out {
        let texture =
            demkit::apps::texture::texture_coordinates(result, &mesh.faces, c.torus.as_ref())?;
        demkit::io::write_textured_obj(uv, &mesh, &texture)?;
    }
    if let Some(png) = &a.render {
        crate::render::render_map(png, &mesh, &c, a)?;
    }
    if let Some(png) = &a.histogram {
        crate::render::render_histograms(png, &mesh, &c, a)?;
    }
    if let Some(path) = &a.report {
        let input = InputSummary {
            vertices: input.n_vertices(),
            faces: input.n_faces(),
            boundaries: topo.boundary_loops.len(),
            genus: topo.genus,
        };
        let report = Report::new(result, input, &metrics, t0.elapsed().as_secs_f64());
        crate::report::write_json(path, &report)?;
    }
    if !a.quiet {
        for n in &result.notes {
            eprintln!("note: {n}");
        }
        eprintln!(
            "{}: {} iterations ({}), density error {:.4}, {} flipped, {:.2} s",
            result.method,
            result.iterations,
            result.stop_reason.as_str(),
            metrics.density_error_mean,
            metrics.flipped_triangles,
            t0.elapsed().as_secs_f64()
        );
    }
    if metrics.flipped_triangles > 0 {
        eprintln!(
            "error: the map has {} flipped triangles",
            metrics.flipped_triangles
        );
        return Ok(1);
    }
    Ok(if result.converged { 0 } else { 3 })
}

/// DEQ's parameters from the command line (paper defaults otherwise).
fn deq_config(a: &MethodArgs) -> deq::Config {
    let mut c = deq::Config::default();
    apply_common(&mut c.epsilon, &mut c.max_iter, &mut c.dt, a);
    c.alpha = a.alpha.unwrap_or(c.alpha);
    c.geometry_update = !a.no_geometry_update;
    c
}

fn apply_common(epsilon: &mut f64, max_iter: &mut usize, dt: &mut Option<f64>, a: &MethodArgs) {
    if let Some(e) = a.epsilon {
        *epsilon = e;
    }
    if let Some(m) = a.max_iter {
        *max_iter = m;
    }
    if a.dt.is_some() {
        *dt = a.dt;
    }
}

/// `--method auto` by topology; explicit methods are checked by the methods themselves.
pub fn resolve_method(a: &MethodArgs, boundaries: usize, genus: i64) -> Result<Method, Failure> {
    if a.method != Method::Auto {
        return Ok(a.method);
    }
    let landmarks = a.landmarks.is_some();
    Ok(match (boundaries, genus, landmarks) {
        (1, 0, false) => Method::Dem,
        (1, 0, true) => Method::Ldeq,
        (b, 0, false) if b > 1 => Method::Deq,
        (b, 0, true) if b > 1 => Method::Ldeq,
        (0, 0, false) => Method::Sdem,
        (0, 0, true) => Method::Lsdem,
        (0, 1, _) => Method::Tdem,
        _ => {
            return Err(Failure::input(format!(
                "no method handles a surface with {boundaries} boundary loops and genus {genus}"
            )));
        }
    })
}

/// `--uv-out` writes .obj only (the format with per-corner texture coordinates).
fn check_uv_extension(path: &Path) -> Result<(), Failure> {
    crate::require_extension(path, &["obj"], "--uv-out writes .obj files")
}

/// `--torus R:r`: the target torus of tdem.
pub fn parse_torus(s: &str) -> Result<Torus, Failure> {
    let parts: Vec<&str> = s.split(':').collect();
    let bad = || {
        Failure::input(format!(
            "--torus must be R:r with numbers R > r > 0 (e.g. 3:1), got '{s}'"
        ))
    };
    if parts.len() != 2 {
        return Err(bad());
    }
    let major: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let minor: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    Torus::new(major, minor).map_err(|e| Failure::input(format!("--torus: {e}")))
}

/// Warns about options the chosen method does not use.
pub fn warn_unused(a: &MethodArgs, m: Method, quiet: bool) {
    if quiet {
        return;
    }
    let unused: Vec<&str> = [
        (
            a.landmarks.is_some()
                && !matches!(
                    m,
                    Method::Lsdem | Method::Sdem | Method::SphericalConformal | Method::Ldeq
                ),
            "--landmarks",
        ),
        (a.torus.is_some() && m != Method::Tdem, "--torus"),
        (
            a.alpha.is_some() && !matches!(m, Method::Lsdem | Method::Deq | Method::Ldeq),
            "--alpha",
        ),
        (a.beta.is_some() && m != Method::Lsdem, "--beta"),
        (
            a.no_geometry_update && !matches!(m, Method::Deq | Method::Ldeq),
            "--no-geometry-update",
        ),
        (a.gamma.is_some() && m != Method::Lsdem, "--gamma"),
        (a.shape.is_some() && m != Method::DemShape, "--shape"),
    ]
    .iter()
    .filter(|(set, _)| *set)
    .map(|(_, n)| *n)
    .collect();
    if !unused.is_empty()
        && matches!(
            m,
            Method::Dem
                | Method::DemShape
                | Method::Sdem
                | Method::Lsdem
                | Method::SphericalConformal
                | Method::Deq
                | Method::Ldeq
                | Method::CircleConformal
                | Method::Tdem
        )
    {
        eprintln!(
            "warning: {} not used by --method {}",
            unused.join(", "),
            m.name()
        );
    }
}
