//! From the harmonic map onto the unit lattice and the lattice assignment to the
//! [`FlatTorusMap`] onto the target rectangle: points wrapped into `[0, 2πR) × [−πr, πr)`,
//! each face drawn around its first corner with whole-period offsets on the other two.

use super::periodic_harmonic::{UnitMap, corner_offset};
use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::{Error, Result};

/// The map `X = diag(2πR, 2πr) P U` of the unit-lattice map `unit` (with the corner offsets of
/// `forms`) for the unimodular `p` (rows: the classes sent onto the `2πR` and `2πr` sides),
/// wrapped: every point moved by whole periods into `[0, 2πR) × [−πr, πr)`, and every face's
/// offsets reduced so that its first corner has none.
///
/// Errors: [`Error::Numerical`] when a point is not finite or an offset does not fit in `i32`
/// (only for a map winding around the torus billions of times).
pub fn flat_map(
    faces: &[[u32; 3]],
    unit: &UnitMap,
    forms: [&[i64]; 2],
    p: [[i64; 2]; 2],
    torus: &Torus,
) -> Result<FlatTorusMap> {
    let [a, b] = torus.periods();
    let points = (0..unit.u[0].len())
        .map(|v| {
            let (u0, u1) = (unit.u[0][v], unit.u[1][v]);
            [
                a * (p[0][0] as f64 * u0 + p[0][1] as f64 * u1),
                b * (p[1][0] as f64 * u0 + p[1][1] as f64 * u1),
            ]
        })
        .collect();
    let offsets = (0..faces.len())
        .map(|f| {
            std::array::from_fn(|k| {
                let n = corner_offset(forms, f, k);
                [
                    p[0][0] * n[0] + p[0][1] * n[1],
                    p[1][0] * n[0] + p[1][1] * n[1],
                ]
            })
        })
        .collect();
    wrapped(points, offsets, faces, torus)
}

/// `map` translated by `shift` (in lengths) and wrapped again as in [`flat_map`].
///
/// Errors: as [`flat_map`].
pub fn translated(
    map: &FlatTorusMap,
    faces: &[[u32; 3]],
    torus: &Torus,
    shift: [f64; 2],
) -> Result<FlatTorusMap> {
    let points = map
        .points
        .iter()
        .map(|p| [p[0] + shift[0], p[1] + shift[1]])
        .collect();
    let offsets = map
        .offsets
        .iter()
        .map(|o| o.map(|c| c.map(i64::from)))
        .collect();
    wrapped(points, offsets, faces, torus)
}

/// The flat torus map with vertex `v` at `points[v]` and corner `k` of face `f` at
/// `points[faces[f][k]] + offsets[f][k] · periods`, every point moved by whole periods into
/// `[0, 2πR) × [−πr, πr)` and every face's offsets reduced so that its first corner has none.
fn wrapped(
    points: Vec<[f64; 2]>,
    offsets: Vec<[[i64; 2]; 3]>,
    faces: &[[u32; 3]],
    torus: &Torus,
) -> Result<FlatTorusMap> {
    let [a, b] = torus.periods();
    let mut out_points = Vec::with_capacity(points.len());
    // Per vertex, the whole periods taken off its point.
    let mut shift = Vec::with_capacity(points.len());
    for p in &points {
        let (f0, k0) = wrap(p[0] / a)?;
        let (f1, k1) = wrap(p[1] / b + 0.5)?;
        out_points.push([a * f0, b * (f1 - 0.5)]);
        shift.push([k0, k1]);
    }
    let mut out_offsets = Vec::with_capacity(faces.len());
    for (f, (t, o)) in faces.iter().zip(&offsets).enumerate() {
        let corner = |k: usize| {
            let s = shift[t[k] as usize];
            [o[k][0] + s[0], o[k][1] + s[1]]
        };
        let base = corner(0);
        let mut out = [[0i32; 2]; 3];
        for (k, c) in out.iter_mut().enumerate().skip(1) {
            let q = corner(k);
            for d in 0..2 {
                c[d] = i32::try_from(q[d] - base[d]).map_err(|_| {
                    Error::Numerical(format!(
                        "face {f}: a lattice offset does not fit in 32 bits"
                    ))
                })?;
            }
        }
        out_offsets.push(out);
    }
    Ok(FlatTorusMap {
        points: out_points,
        offsets: out_offsets,
    })
}

/// `x = k + frac` with `k` an integer and `frac ∈ [0, 1)` (exactly, after rounding).
fn wrap(x: f64) -> Result<(f64, i64)> {
    if !(x.is_finite() && x.abs() < 1e15) {
        return Err(Error::Numerical(format!(
            "the flat torus map has a point at {x} periods"
        )));
    }
    let k = x.floor();
    let mut frac = x - k;
    let mut k = k as i64;
    if frac >= 1.0 {
        frac = 0.0;
        k += 1;
    }
    Ok((frac, k))
}
