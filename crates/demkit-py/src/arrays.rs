//! Conversions between numpy arrays and the library's vertex and face lists.

use crate::input_error;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

/// A mesh as numpy arrays: (n, 3) float64 vertices and (m, 3) int64 faces.
pub type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// Vertex positions from an (n, 3) float64 array.
pub fn positions(a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 3]>> {
    let v = a.as_array();
    if v.ncols() != 3 {
        return Err(input_error(format!(
            "vertices must be an (n, 3) or (n, 2) array, got shape {:?}",
            v.shape()
        )));
    }
    Ok(v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect())
}

/// Faces from an (m, 3) int64 array; an index below 0 or beyond `u32` is refused here, one
/// beyond the vertices by the library's validation.
pub fn faces(a: &PyReadonlyArray2<'_, i64>) -> PyResult<Vec<[u32; 3]>> {
    let f = a.as_array();
    if f.ncols() != 3 {
        return Err(input_error(format!(
            "faces must be an (m, 3) integer array, got shape {:?}",
            f.shape()
        )));
    }
    let mut out = Vec::with_capacity(f.nrows());
    for (i, r) in f.rows().into_iter().enumerate() {
        let mut face = [0u32; 3];
        for (k, &x) in r.iter().enumerate() {
            face[k] = u32::try_from(x).map_err(|_| {
                input_error(format!(
                    "invalid mesh: face {i} uses vertex {x}, which is out of range"
                ))
            })?;
        }
        out.push(face);
    }
    Ok(out)
}

/// Per-face or per-landmark values from an (m,) float64 array.
pub fn values(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    a.as_array().iter().copied().collect()
}

/// An (n, 3) float64 array of points.
pub fn points_array<'py>(py: Python<'py>, p: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = p.iter().flatten().copied().collect();
    Array2::from_shape_vec((p.len(), 3), flat)
        .expect("n × 3 values")
        .into_pyarray(py)
}

/// An (m, 3) int64 array of faces.
pub fn faces_array<'py>(py: Python<'py>, f: &[[u32; 3]]) -> Bound<'py, PyArray2<i64>> {
    let flat: Vec<i64> = f.iter().flatten().map(|&i| i64::from(i)).collect();
    Array2::from_shape_vec((f.len(), 3), flat)
        .expect("m × 3 values")
        .into_pyarray(py)
}
