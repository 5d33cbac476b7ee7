//! `map` and `remesh`: a density-equalizing map of numpy arrays, computed with the GIL released.

use crate::arrays::{MeshArrays, faces, faces_array, points_array, positions, values};
use crate::{guarded, input_error, to_py};
use demkit::geometry::ellipsoid::Ellipsoid;
use demkit::geometry::torus::Torus;
use demkit::methods::Progress;
use demkit::shape::Shape;
use demkit::{Domain, MapOptions, Method, Population, Surface};
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::time::Instant;

/// The names of every method, `auto` first.
#[pyfunction]
pub fn methods() -> Vec<&'static str> {
    Method::ALL.iter().map(|m| m.name()).collect()
}

/// Everything a map is computed from, as the Python layer passes it.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct Request<'py> {
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    /// `"area"`, `"uniform"` or an expression; ignored when `population_values` is given.
    population: String,
    population_values: Option<PyReadonlyArray1<'py, f64>>,
    method: String,
    landmark_indices: Option<PyReadonlyArray1<'py, i64>>,
    landmark_targets: Option<PyReadonlyArray2<'py, f64>>,
    torus: Option<(f64, f64)>,
    ellipsoid: Option<(f64, f64, f64)>,
    shape: Option<String>,
    alpha: Option<f64>,
    beta: Option<f64>,
    gamma: Option<f64>,
    dt: Option<f64>,
    epsilon: Option<f64>,
    max_iter: Option<usize>,
    fixed_holes: bool,
}

/// A request read into the library's types.
struct Prepared {
    surface: Surface,
    population: Population,
    options: MapOptions,
}

fn method_named(name: &str) -> PyResult<Method> {
    Method::ALL
        .iter()
        .copied()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            input_error(format!(
                "unknown method '{name}' (one of {})",
                methods().join(", ")
            ))
        })
}

fn prepare(r: &Request<'_>) -> PyResult<Prepared> {
    let surface = Surface::new(positions(&r.vertices)?, faces(&r.faces)?).map_err(to_py)?;
    let n = surface.mesh().n_vertices();
    let topo = surface.topology();
    let has_landmarks = r.landmark_indices.is_some();
    let method = method_named(&r.method)?
        .resolve(
            topo.boundary_loops.len(),
            topo.genus,
            has_landmarks,
            r.ellipsoid.is_some(),
        )
        .map_err(to_py)?;
    let population = match &r.population_values {
        Some(v) => Population::PerFace(values(v)),
        None => match r.population.as_str() {
            "area" => Population::Area,
            "uniform" => Population::Uniform,
            e => Population::Expression(e.to_string()),
        },
    };
    let takes_landmarks = matches!(
        method,
        Method::Lsdem | Method::Sdem | Method::SphericalConformal | Method::Ldeq
    );
    let landmarks = match (&r.landmark_indices, &r.landmark_targets) {
        (Some(i), Some(t)) if takes_landmarks => landmarks(i, t, n)?,
        _ => Vec::new(),
    };
    if matches!(method, Method::Lsdem | Method::Ldeq) && landmarks.is_empty() {
        return Err(input_error(format!(
            "method '{}' needs landmarks: vertex indices and their targets ({})",
            method.name(),
            if method == Method::Lsdem {
                "on the unit sphere"
            } else {
                "in the unit disk"
            }
        )));
    }
    let torus = match (r.torus, method) {
        (Some((big, small)), Method::Tdem) => {
            Some(Torus::new(big, small).map_err(|e| input_error(format!("torus: {e}")))?)
        }
        (None, Method::Tdem) => {
            return Err(input_error(
                "method 'tdem' (for genus-one closed surfaces) needs the target torus: torus=(R, r) with R > r > 0",
            ));
        }
        _ => None,
    };
    let ellipsoid = match (r.ellipsoid, method) {
        (Some((a, b, c)), Method::Edem | Method::Edeq) => {
            Some(Ellipsoid::new(a, b, c).map_err(|e| input_error(format!("ellipsoid: {e}")))?)
        }
        (None, Method::Edem) => {
            return Err(input_error(
                "method 'edem' needs the target ellipsoid: ellipsoid=(a, b, c) with a, b, c > 0",
            ));
        }
        _ => None,
    };
    let shape = match (&r.shape, method) {
        (Some(s), Method::DemShape) => Some(Shape::parse(s).map_err(to_py)?),
        _ => None,
    };
    let options = MapOptions {
        method,
        landmarks,
        torus,
        ellipsoid,
        shape,
        alpha: r.alpha,
        beta: r.beta,
        gamma: r.gamma,
        dt: r.dt,
        epsilon: r.epsilon,
        max_iter: r.max_iter,
        fixed_holes: r.fixed_holes,
    };
    Ok(Prepared {
        surface,
        population,
        options,
    })
}

/// Landmarks from (k,) indices and (k, 3) targets (the Python layer pads 2D targets with 0).
fn landmarks(
    indices: &PyReadonlyArray1<'_, i64>,
    targets: &PyReadonlyArray2<'_, f64>,
    n: usize,
) -> PyResult<Vec<(usize, [f64; 3])>> {
    let (i, t) = (indices.as_array(), targets.as_array());
    if t.ncols() != 3 || t.nrows() != i.len() {
        return Err(input_error(format!(
            "invalid landmarks: {} indices but targets of shape {:?} (expected ({}, 2) or ({}, 3))",
            i.len(),
            t.shape(),
            i.len(),
            i.len()
        )));
    }
    let mut out = Vec::with_capacity(i.len());
    for (k, (&v, row)) in i.iter().zip(t.rows()).enumerate() {
        let vertex = usize::try_from(v).ok().filter(|&v| v < n).ok_or_else(|| {
            input_error(format!(
                "invalid landmarks: landmark {k} names vertex {v}, which is out of range (the mesh has {n} vertices)"
            ))
        })?;
        let target = [row[0], row[1], row[2]];
        if !target.iter().all(|x| x.is_finite()) {
            return Err(input_error(format!(
                "invalid landmarks: landmark {k} has a target that is not finite"
            )));
        }
        out.push((vertex, target));
    }
    Ok(out)
}

/// Runs the map with the GIL released, reporting each iteration to `progress` (called with
/// `(iteration, error, max_iter)` under the GIL); the first exception `progress` raises is
/// raised once the map is done. The map runs on a thread of rayon's pool, as the command line
/// runs it: the library's parallel loops then start from a worker instead of being handed to
/// the pool from outside, one sleep and wake-up each.
fn run(py: Python<'_>, p: &Prepared, progress: Option<Py<PyAny>>) -> PyResult<demkit::Map> {
    let mut failed: Option<PyErr> = None;
    let map = py.detach(|| {
        guarded(|| {
            rayon::scope(|_| {
                let mut report = |s: Progress| {
                    if let Some(cb) = &progress
                        && failed.is_none()
                    {
                        Python::attach(|py| {
                            if let Err(e) = cb.call1(py, (s.iteration, s.error, s.max_iter)) {
                                failed = Some(e);
                            }
                        });
                    }
                };
                demkit::map_with_progress(&p.surface, &p.population, &p.options, &mut report)
                    .map_err(to_py)
            })
        })
    });
    if let Some(e) = failed {
        return Err(e);
    }
    map
}

/// Computes a map; returns a dict of numpy arrays and plain values the Python `Map` wraps.
#[pyfunction]
#[pyo3(signature = (request, progress=None))]
pub fn map<'py>(
    py: Python<'py>,
    request: Request<'py>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let t0 = Instant::now();
    let prepared = prepare(&request)?;
    let map = run(py, &prepared, progress)?;
    let report = map.report(&prepared.surface, t0.elapsed().as_secs_f64());
    let report = serde_json::to_string(&report)
        .map_err(|e| crate::NumericalError::new_err(e.to_string()))?;
    let mut initial = map.result.initial.clone();
    if matches!(map.domain, Domain::Torus { .. }) {
        demkit::mesh::scale::scale_positions(&mut initial, -prepared.surface.exponent());
    }
    let out = PyDict::new(py);
    out.set_item("vertices", points_array(py, &map.positions))?;
    out.set_item("initial", points_array(py, &initial))?;
    out.set_item("faces", faces_array(py, &map.mesh.faces))?;
    out.set_item("population", map.population.clone())?;
    out.set_item("method", map.method.name())?;
    out.set_item("report", report)?;
    out.set_item("warnings", prepared.surface.warnings().to_vec())?;
    let domain = PyDict::new(py);
    match &map.domain {
        Domain::Plane => domain.set_item("kind", "plane")?,
        Domain::Sphere => domain.set_item("kind", "sphere")?,
        Domain::Ellipsoid { a, b, c } => {
            domain.set_item("kind", "ellipsoid")?;
            domain.set_item("radii", (*a, *b, *c))?;
        }
        Domain::CircleDomain { circles } => {
            domain.set_item("kind", "circle_domain")?;
            let list = PyList::empty(py);
            for (c, r) in circles {
                list.append(((c[0], c[1]), *r))?;
            }
            domain.set_item("circles", list)?;
        }
        Domain::Torus { torus, .. } => {
            domain.set_item("kind", "torus")?;
            domain.set_item("torus", (torus.major, torus.minor))?;
        }
    }
    out.set_item("domain", domain)?;
    Ok(out)
}

/// Remeshes a surface through its map with about `n` vertices; returns (vertices, faces).
#[pyfunction]
#[pyo3(signature = (request, n, progress=None))]
pub fn remesh<'py>(
    py: Python<'py>,
    request: Request<'py>,
    n: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<MeshArrays<'py>> {
    use demkit::apps::remesh::{DEQ_ALPHA, Target, check_vertex_count, min_vertices, remesh};
    let mut prepared = prepare(&request)?;
    let o = &mut prepared.options;
    if matches!(o.method, Method::Deq | Method::Ldeq) && o.alpha.is_none() {
        o.alpha = Some(DEQ_ALPHA);
    }
    check_vertex_count(n).map_err(to_py)?;
    let topo = prepared.surface.topology();
    let least = min_vertices(topo.boundary_loops.len(), topo.genus);
    if n < least {
        return Err(input_error(format!(
            "vertices must be at least {least} for a surface with {} boundary loops and genus {}, got {n}",
            topo.boundary_loops.len(),
            topo.genus
        )));
    }
    let map = run(py, &prepared, progress)?;
    if map.metrics.flipped_triangles > 0 {
        return Err(crate::NumericalError::new_err(format!(
            "the {} map has {} flipped triangles; the inverse map is not defined there, so the surface cannot be remeshed through it",
            map.method.name(),
            map.metrics.flipped_triangles
        )));
    }
    let exponent = prepared.surface.exponent();
    let torus = prepared
        .options
        .torus
        .map(|t| t.scaled_by_power_of_two(exponent));
    let out = py.detach(|| {
        guarded(|| {
            let target = match (&map.result.flat_torus, &torus, map.result.ellipsoid) {
                (Some(map), Some(torus), _) => Target::Torus { map, torus },
                (_, _, Some(e)) => Target::Ellipsoid(e),
                _ if map.method.maps_onto_sphere() => Target::Sphere,
                _ => Target::Plane,
            };
            let mut out = remesh(&map.mesh, &map.population, &map.result.positions, target, n)
                .map_err(to_py)?;
            demkit::mesh::scale::scale_positions(&mut out.positions, -exponent);
            Ok(out)
        })
    })?;
    Ok((
        points_array(py, &out.positions),
        faces_array(py, &out.faces),
    ))
}
