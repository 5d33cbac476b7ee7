//! Mesh files, generated meshes, metrics of a given map and cartograms.

use crate::arrays::{MeshArrays, faces, faces_array, points_array, positions, values};
use crate::{guarded, input_error, to_py};
use carto::{Config, Positions, geojson, planar, values::ValueSource};
use demkit::TriMesh;
use demkit::apps::cartogram as carto;
use demkit::generate as g;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

fn mesh_arrays<'py>(py: Python<'py>, mesh: &TriMesh) -> MeshArrays<'py> {
    (
        points_array(py, &mesh.positions),
        faces_array(py, &mesh.faces),
    )
}

/// Reads a mesh file (.obj, .ply, .off, .stl); returns (vertices, faces).
#[pyfunction]
pub fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<MeshArrays<'_>> {
    let mesh = py.detach(|| guarded(|| demkit::io::read_mesh(&path).map_err(to_py)))?;
    Ok(mesh_arrays(py, &mesh))
}

/// Writes a mesh file (.obj or .ply), atomically.
#[pyfunction]
pub fn write_mesh(
    py: Python<'_>,
    path: PathBuf,
    vertices: PyReadonlyArray2<'_, f64>,
    faces_: PyReadonlyArray2<'_, i64>,
) -> PyResult<()> {
    let positions = positions(&vertices)?;
    let faces = faces(&faces_)?;
    let n = positions.len();
    if let Some((i, v)) = faces
        .iter()
        .enumerate()
        .find_map(|(i, f)| f.iter().find(|&&v| v as usize >= n).map(|&v| (i, v)))
    {
        return Err(input_error(format!(
            "invalid mesh: face {i} uses vertex {v}, which is out of range (the mesh has {n} vertices)"
        )));
    }
    let mesh = TriMesh::new(positions, faces);
    py.detach(|| guarded(|| demkit::io::write_mesh(&path, &mesh).map_err(to_py)))
}

/// The surface (`vertices`, `faces`) with holes cut around points (`demkit cut`): `holes`
/// as (x, y, z, r); `planar` measures distances in the plane z = 0. Returns (vertices,
/// faces) of the cut surface, its vertices in their input order.
#[pyfunction]
#[pyo3(signature = (vertices, faces_, holes, planar))]
pub fn cut_holes<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces_: PyReadonlyArray2<'py, i64>,
    holes: Vec<(f64, f64, f64, f64)>,
    planar: bool,
) -> PyResult<MeshArrays<'py>> {
    let mesh = TriMesh::new(positions(&vertices)?, faces(&faces_)?);
    let holes: Vec<demkit::mesh::Hole> = holes
        .into_iter()
        .map(|(x, y, z, radius)| demkit::mesh::Hole {
            centre: [x, y, z],
            radius,
        })
        .collect();
    let cut =
        py.detach(|| guarded(|| demkit::mesh::cut_holes(&mesh, &holes, planar).map_err(to_py)))?;
    Ok(mesh_arrays(py, &cut))
}

/// An option of `generate`, or its default.
fn option<'py, T: for<'a> FromPyObject<'a, 'py>>(
    options: &Bound<'py, PyDict>,
    name: &str,
    default: T,
) -> PyResult<T> {
    match options.get_item(name)? {
        Some(v) => v
            .extract()
            .map_err(|_| input_error(format!("generate: option '{name}' has the wrong type"))),
        None => Ok(default),
    }
}

/// The options each kind takes (the command line's, with its defaults).
const KINDS: [(&str, &[&str]); 11] = [
    ("grid", &["nx", "ny", "width", "height"]),
    ("polygon", &["sides", "rings"]),
    ("peaks", &["n"]),
    ("gaussian", &["n"]),
    ("annulus", &["inner", "outer", "radial", "angular"]),
    ("disk-holes", &["holes", "resolution"]),
    ("rect-holes", &["width", "height", "holes", "resolution"]),
    ("icosphere", &["subdivisions"]),
    ("uv-sphere", &["lat", "lon"]),
    ("torus", &["R", "r", "major", "minor"]),
    ("sphere", &["subdivisions"]),
];

/// A synthetic mesh of `kind` with `options` (as `demkit generate KIND` names them).
#[pyfunction]
#[pyo3(signature = (kind, options))]
pub fn generate<'py>(
    py: Python<'py>,
    kind: &str,
    options: &Bound<'py, PyDict>,
) -> PyResult<MeshArrays<'py>> {
    let kind = kind.replace('_', "-");
    let Some((_, known)) = KINDS.iter().find(|(k, _)| *k == kind) else {
        let names: Vec<&str> = KINDS.iter().map(|(k, _)| *k).collect();
        return Err(input_error(format!(
            "generate: unknown kind '{kind}' (one of {})",
            names.join(", ")
        )));
    };
    for key in options.keys() {
        let key: String = key.extract()?;
        if !known.contains(&key.as_str()) {
            return Err(input_error(format!(
                "generate('{kind}') takes {}; got '{key}'",
                known.join(", ")
            )));
        }
    }
    let o = options;
    let holes: Vec<(f64, f64, f64)> = option(o, "holes", Vec::new())?;
    let mesh = match kind.as_str() {
        "grid" => g::square_grid(
            option(o, "nx", 99)?,
            option(o, "ny", 99)?,
            option(o, "width", 99.0)?,
            option(o, "height", 99.0)?,
        ),
        "polygon" => g::regular_polygon(option(o, "sides", 6)?, option(o, "rings", 32)?),
        "peaks" => g::peaks(option(o, "n", 45)?),
        "gaussian" => g::gaussian(option(o, "n", 72)?),
        "annulus" => g::annulus(
            option(o, "inner", 0.4)?,
            option(o, "outer", 1.0)?,
            option(o, "radial", 12)?,
            option(o, "angular", 96)?,
        ),
        "disk-holes" => g::disk_with_holes(&holes, option(o, "resolution", 40)?),
        "rect-holes" => g::rectangle_with_holes(
            option(o, "width", 2.0)?,
            option(o, "height", 1.0)?,
            &holes,
            option(o, "resolution", 40)?,
        ),
        "icosphere" | "sphere" => g::icosphere(option(o, "subdivisions", 4)?),
        "uv-sphere" => g::uv_sphere(option(o, "lat", 32)?, option(o, "lon", 64)?),
        _ => g::torus(
            option(o, "R", 2.0)?,
            option(o, "r", 1.0)?,
            option(o, "major", 64)?,
            option(o, "minor", 32)?,
        ),
    }
    .map_err(to_py)?;
    Ok(mesh_arrays(py, &mesh))
}

/// The report's metrics (as JSON text) of the map `initial → mapped` of the surface
/// (`vertices`, `faces`) with `population` (a name or an expression) or `population_values`
/// (per face, any positive scale); `domain` is
/// `"plane"` or `"sphere"`.
#[pyfunction]
#[pyo3(signature = (vertices, faces_, mapped, initial, population, population_values, domain, landmark_indices=None, landmark_targets=None))]
#[allow(clippy::too_many_arguments)]
pub fn metrics(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f64>,
    faces_: PyReadonlyArray2<'_, i64>,
    mapped: PyReadonlyArray2<'_, f64>,
    initial: PyReadonlyArray2<'_, f64>,
    population: &str,
    population_values: Option<PyReadonlyArray1<'_, f64>>,
    domain: &str,
    landmark_indices: Option<PyReadonlyArray1<'_, i64>>,
    landmark_targets: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<String> {
    let mesh = TriMesh::new(positions(&vertices)?, faces(&faces_)?);
    let (mapped, initial) = (positions(&mapped)?, positions(&initial)?);
    let n = mesh.n_vertices();
    if mapped.len() != n || initial.len() != n {
        return Err(input_error(format!(
            "the maps must have one point per vertex ({n}), got {} and {}",
            mapped.len(),
            initial.len()
        )));
    }
    let domain = match domain {
        "plane" => demkit::metrics::Domain::Plane,
        "sphere" => demkit::metrics::Domain::Sphere,
        d => {
            return Err(input_error(format!(
                "domain must be 'plane' or 'sphere', got '{d}'"
            )));
        }
    };
    let landmarks: Vec<(usize, [f64; 3])> = match (landmark_indices, landmark_targets) {
        (Some(i), Some(t)) => i
            .as_array()
            .iter()
            .zip(t.as_array().rows())
            .map(|(&v, r)| (v as usize, [r[0], r[1], r[2]]))
            .collect(),
        _ => Vec::new(),
    };
    // Validation only (indices, finite coordinates, manifold); the input is measured as given.
    demkit::Surface::from_mesh(mesh.clone()).map_err(to_py)?;
    let population = match population_values {
        Some(v) => {
            let v = values(&v);
            demkit::population::check_population(&v, mesh.n_faces()).map_err(to_py)?;
            v
        }
        None => {
            use demkit::population::{PopulationSpec, face_populations_at_scale};
            let spec = match population {
                "area" => PopulationSpec::Area,
                "uniform" => PopulationSpec::Uniform,
                e => PopulationSpec::Expr(e.to_string()),
            };
            face_populations_at_scale(&spec, &mesh, 0).map_err(to_py)?
        }
    };
    if let Some(&(v, _)) = landmarks.iter().find(|(v, _)| *v >= n) {
        return Err(input_error(format!(
            "invalid landmarks: vertex {v} is out of range (the mesh has {n} vertices)"
        )));
    }
    let m = py.detach(|| {
        guarded(|| {
            let unit = demkit::population::unit_scale(&population);
            Ok(demkit::metrics::compute(
                &mesh,
                &unit,
                &initial,
                &mapped,
                domain,
                (!landmarks.is_empty()).then_some(&landmarks[..]),
            ))
        })
    })?;
    serde_json::to_string(&m).map_err(|e| crate::NumericalError::new_err(e.to_string()))
}

/// A cartogram of the GeoJSON `text` (named `label` in messages), each region's area following
/// the numeric property `value`; returns (GeoJSON text, notes, converged).
#[pyfunction]
#[pyo3(signature = (text, label, value, sphere=false, project=false, max_error=0.01, grid=1024, max_iter=None))]
#[allow(clippy::too_many_arguments)]
pub fn cartogram(
    py: Python<'_>,
    text: String,
    label: String,
    value: String,
    sphere: bool,
    project: bool,
    max_error: f64,
    grid: usize,
    max_iter: Option<usize>,
) -> PyResult<(String, Vec<String>, bool)> {
    if sphere && project {
        return Err(input_error("sphere and project exclude each other"));
    }
    if !(max_error.is_finite() && max_error > 0.0) {
        return Err(input_error(format!(
            "max_error must be a positive number (a relative error, 0.01 for 1 %), got {max_error}"
        )));
    }
    if max_iter == Some(0) {
        return Err(input_error("max_iter must be at least 1"));
    }
    planar::check_grid(grid).map_err(to_py)?;
    let positions = if sphere {
        Positions::Sphere
    } else if project {
        Positions::Project
    } else {
        Positions::Plane
    };
    py.detach(|| {
        guarded(|| {
            let source = ValueSource::Property(&value);
            let (fc, set) =
                carto::load_text(&text, &label, &source, positions).map_err(to_py)?;
            let config = Config {
                max_iter,
                tolerance: max_error,
                grid,
                ..Config::default()
            };
            let c = if sphere {
                carto::sphere::run(&set, &config, &label, &mut |_| {})
            } else {
                planar::run(&set, &config, &label, &mut |_| {})
            }
            .map_err(to_py)?;
            let mut notes = set.warnings.clone();
            notes.extend(c.run.notes.iter().cloned());
            let converged = c.max_error <= max_error;
            if !converged {
                notes.push(format!(
                    "not converged: the worst region, {}, is {:.2}% off its share (asked: within {:.2}%)",
                    c.max_error_region,
                    100.0 * c.max_error,
                    100.0 * max_error
                ));
            }
            let out = geojson::replace_coordinates(&fc, &c.coordinates);
            Ok((geojson::to_text(out), notes, converged))
        })
    })
}
