//! `demkit map`: read, validate, map, write the mesh and the report.

use crate::Failure;
use crate::args::{MapArgs, MethodArgs};
use crate::progress::Bar;
use demkit::geometry::ellipsoid::Ellipsoid;
use demkit::geometry::torus::Torus;
use demkit::population::{PopulationSpec, face_populations_at_scale};
use demkit::shape::Shape;
use demkit::{MapOption, MapOptions, Method, Population, Surface, TriMesh};
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
    /// The map ([`demkit::map`]): the surface mapped, its population, positions, domain,
    /// metrics and the method's result.
    pub map: demkit::Map,
    /// The target torus of tdem, in the computation's units (as the flat map has it).
    pub torus: Option<Torus>,
}

impl Computed {
    /// The surface mapped (the input, or its refinement).
    pub fn mesh(&self) -> &TriMesh {
        &self.map.mesh
    }
}

/// Computes the density-equalizing map of `surface` with the options of `map` and `remesh`;
/// `method` comes from [`resolve_method`].
pub fn compute(
    surface: &Surface,
    method: Method,
    a: &MethodArgs,
    quiet: bool,
) -> Result<Computed, Failure> {
    let mesh = surface.mesh();
    let population = match crate::paths::population_spec(&a.population) {
        PopulationSpec::Area => Population::Area,
        PopulationSpec::Uniform => Population::Uniform,
        PopulationSpec::Expr(e) => Population::Expression(e),
        spec @ PopulationSpec::File(_) => {
            Population::PerFace(face_populations_at_scale(&spec, mesh, surface.exponent())?)
        }
    };
    let landmarks: Vec<(usize, [f64; 3])> = match &a.landmarks {
        Some(path)
            if matches!(
                method,
                Method::Lsdem | Method::Sdem | Method::SphericalConformal | Method::Ldeq
            ) =>
        {
            let l = demkit::io::landmarks::read_landmarks(path, mesh.n_vertices())?;
            l.into_iter().map(|l| (l.vertex, l.target)).collect()
        }
        _ => Vec::new(),
    };
    if method == Method::Lsdem && landmarks.is_empty() {
        return Err(Failure::input(
            "--method lsdem needs --landmarks FILE (vertex_index x y z per line)",
        ));
    }
    if method == Method::Ldeq && landmarks.is_empty() {
        return Err(Failure::input(
            "--method ldeq needs --landmarks FILE (vertex_index x y per line)",
        ));
    }
    let torus = match (&a.torus, method) {
        (Some(s), Method::Tdem) => Some(parse_torus(s)?),
        (None, Method::Tdem) => {
            return Err(Failure::input(
                "--method tdem (for genus-one closed surfaces) needs the target torus: --torus R:r with R > r > 0",
            ));
        }
        _ => None,
    };
    let ellipsoid = match (&a.ellipsoid, method) {
        (Some(s), Method::Edem | Method::Edeq) => Some(parse_ellipsoid(s)?),
        (None, Method::Edem) => {
            return Err(Failure::input(
                "--method edem needs the target ellipsoid: --ellipsoid A:B:C with radii A, B, C > 0",
            ));
        }
        _ => None,
    };
    let shape = match (&a.shape, method) {
        (Some(s), Method::DemShape) => Some(Shape::parse(s)?),
        _ => None,
    };
    let options = MapOptions {
        method,
        landmarks,
        torus,
        ellipsoid,
        shape,
        ..numeric_options(a)
    };
    let bar = Bar::new(quiet, method.name());
    let map = demkit::map_with_progress(surface, &population, &options, &mut |p| bar.update(p));
    bar.finish();
    let map = map?;
    Ok(Computed {
        method,
        map,
        torus: torus.map(|t| t.scaled_by_power_of_two(surface.exponent())),
    })
}

/// Runs the map command; returns the exit code (0, or 3 when not converged).
pub fn run(a: &MapArgs) -> Result<u8, Failure> {
    let t0 = Instant::now();
    check_output_extension(&a.out)?;
    if let Some(uv) = &a.uv_out {
        check_uv_extension(uv)?;
    }
    crate::render::check_map_args(a, a.quiet)?;
    check_values(&a.m)?;
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
    let surface = crate::surface::read_valid_mesh(&a.mesh, a.quiet)?;
    let topo = surface.topology();
    let method = resolve_method(&a.m, topo.boundary_loops.len(), topo.genus)?;
    warn_unused(&a.m, method, a.quiet);
    if a.uv_out.is_some() && method.maps_onto_closed_surface() {
        return Err(Failure::input(format!(
            "--uv-out needs a planar, circle-domain or torus map, and --method {} maps onto {}",
            method.name(),
            if method.maps_onto_sphere() {
                "the sphere"
            } else {
                "an ellipsoid"
            }
        )));
    }
    let c = compute(&surface, method, &a.m, a.quiet)?;
    let metrics = &c.map.metrics;
    let result = &c.map.result;
    let mesh = c.mesh();
    let out_mesh = TriMesh::new(c.map.positions.clone(), mesh.faces.clone());
    demkit::io::write_mesh(&a.out, &out_mesh)?;
    if let Some(uv) = &a.uv_out {
        let texture =
            demkit::apps::texture::texture_coordinates(result, &mesh.faces, c.torus.as_ref())?;
        demkit::io::write_textured_obj(uv, mesh, &texture)?;
    }
    if let Some(png) = &a.render {
        crate::render::render_map(png, mesh, &c.map, a)?;
    }
    if let Some(png) = &a.histogram {
        crate::render::render_histograms(png, mesh, &c.map, a)?;
    }
    if let Some(path) = &a.report {
        let report = c.map.report(&surface, t0.elapsed().as_secs_f64());
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
    // A refused run (the method could not compute its map: the reason is in the notes) is not
    // converged, exit 3, whatever its stand-in; any other map with flipped triangles is an
    // error.
    if metrics.flipped_triangles > 0 && !result.refused {
        eprintln!(
            "error: the map has {} flipped triangles",
            metrics.flipped_triangles
        );
        return Ok(1);
    }
    Ok(if result.converged { 0 } else { 3 })
}

/// `--method auto` by topology; explicit methods are checked by the methods themselves.
pub fn resolve_method(a: &MethodArgs, boundaries: usize, genus: i64) -> Result<Method, Failure> {
    Ok(a.method.0.resolve(
        boundaries,
        genus,
        a.landmarks.is_some(),
        a.ellipsoid.is_some(),
    )?)
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

/// `--ellipsoid A:B:C`: the target ellipsoid of edem.
pub fn parse_ellipsoid(s: &str) -> Result<Ellipsoid, Failure> {
    let bad = || {
        Failure::input(format!(
            "--ellipsoid must be A:B:C with numbers A, B, C > 0 (e.g. 1:1:2), got '{s}'"
        ))
    };
    let radii: Vec<f64> = s
        .split(':')
        .map(|x| x.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    let [a, b, c] = radii[..] else {
        return Err(bad());
    };
    Ellipsoid::new(a, b, c).map_err(|e| Failure::input(format!("--ellipsoid: {e}")))
}

/// The library's options that `a` sets (a landmark file counts before it is read).
fn options_set(a: &MethodArgs) -> Vec<MapOption> {
    let mut set = demkit::options::set_in(&numeric_options(a));
    for (given, option) in [
        (a.landmarks.is_some(), MapOption::Landmarks),
        (a.torus.is_some(), MapOption::Torus),
        (a.shape.is_some(), MapOption::Shape),
        (a.ellipsoid.is_some(), MapOption::Ellipsoid),
    ] {
        if given {
            set.push(option);
        }
    }
    set
}

/// The numbers and switches of `a` as the library's options (no landmarks, torus or shape).
fn numeric_options(a: &MethodArgs) -> MapOptions {
    MapOptions {
        method: a.method.0,
        alpha: a.weights.alpha,
        beta: a.weights.beta,
        gamma: a.weights.gamma,
        dt: a.dt,
        epsilon: a.stop.epsilon,
        max_iter: a.stop.max_iter,
        fixed_holes: a.no_geometry_update,
        ..MapOptions::default()
    }
}

/// Refuses, before anything is read, a value out of range whichever method would read it
/// ([`demkit::options::check_values`]): a negative or non-finite weight, time step or
/// tolerance.
pub fn check_values(a: &MethodArgs) -> Result<(), Failure> {
    if let Some(s) = &a.ellipsoid {
        parse_ellipsoid(s)?;
    }
    Ok(demkit::options::check_values(&numeric_options(a))?)
}

/// Warns about the options the chosen method does not read ([`Method::options`]).
pub fn warn_unused(a: &MethodArgs, m: Method, quiet: bool) {
    let unused = demkit::options::unused(m, &options_set(a));
    if quiet || unused.is_empty() {
        return;
    }
    let flags: Vec<&str> = unused.iter().map(|o| crate::flag(o.name())).collect();
    eprintln!(
        "warning: {} not used by --method {}",
        flags.join(", "),
        m.name()
    );
}
