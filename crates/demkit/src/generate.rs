//! Synthetic meshes for examples, tests and benchmarks (`demkit generate KIND ...`).
//!
//! Every generator is deterministic (no randomness, no jitter), returns faces ordered
//! counter-clockwise — seen from +z for planar meshes, seen from outside for closed ones — and
//! never repeats a vertex. Invalid parameters (a count too small, a radius that is not positive
//! and finite, a mesh too large for `u32` indices, ...) give [`Error::Argument`] naming the
//! parameter; nothing panics.
//!
//! | function | topology | vertices | faces |
//! | --- | --- | --- | --- |
//! | [`square_grid`]`(nx, ny, w, h)` | disk | (nx+1)(ny+1) | 2·nx·ny |
//! | [`height_field`], [`peaks`]`(n)`, [`gaussian`]`(n)` | disk | (n+1)² | 2n² |
//! | [`regular_polygon`]`(s, k)` | disk | 1 + s·k(k+1)/2 | s·k² |
//! | [`annulus`]`(r, R, nr, na)` | annulus | (nr+1)·na | 2·nr·na |
//! | [`disk_with_holes`]`(holes, n)` | disk minus k holes | depends on the Delaunay mesh | |
//! | [`rectangle_with_holes`]`(w, h, holes, n)` | rectangle minus k holes | depends on the Delaunay mesh | |
//! | [`icosphere`]`(s)` | sphere | 10·4^s + 2 | 20·4^s |
//! | [`uv_sphere`]`(nl, nm)` | sphere | 2 + (nl−1)·nm | 2·nm·(nl−1) |
//! | [`torus`]`(R, r, nu, nv)` | torus | nu·nv | 2·nu·nv |

mod closed;
mod grid;
mod planar;

pub use closed::{icosphere, torus, uv_sphere};
pub use grid::{
    GAUSSIAN_PAPER_N, PEAKS_PAPER_N, gaussian, gaussian_function, height_field, peaks,
    peaks_function, square_grid,
};
pub use planar::{annulus, disk_with_holes, rectangle_with_holes, regular_polygon};

use crate::{Error, Result};

/// Splits every quad cell `(p, q)` — corners `index(p, q)`, `index(p + 1, q)`,
/// `index(p + 1, q + 1)`, `index(p, q + 1)`, counter-clockwise — into two triangles along the
/// same diagonal, in the order the cells come. Shared by the grid, annulus, UV sphere and torus.
fn split_cells(
    cells: impl Iterator<Item = (usize, usize)>,
    index: impl Fn(usize, usize) -> u32,
    capacity: usize,
) -> Vec<[u32; 3]> {
    let mut faces = Vec::with_capacity(capacity);
    for (p, q) in cells {
        let (a, b, c, d) = (
            index(p, q),
            index(p + 1, q),
            index(p + 1, q + 1),
            index(p, q + 1),
        );
        faces.push([a, b, c]);
        faces.push([a, c, d]);
    }
    faces
}

/// Refuses a count below `min`.
fn at_least(name: &str, value: usize, min: usize) -> Result<()> {
    if value < min {
        Err(Error::Argument(format!(
            "{name} must be at least {min}, got {value}"
        )))
    } else {
        Ok(())
    }
}

/// Refuses a length that is not finite and positive.
fn positive(name: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::Argument(format!(
            "{name} must be positive and finite, got {value}"
        )))
    }
}

/// Refuses a pair of lengths `(name, value)` where the first is not smaller than the second.
fn smaller(small: (&str, f64), big: (&str, f64)) -> Result<()> {
    let ((small_name, small), (big_name, big)) = (small, big);
    if small < big {
        Ok(())
    } else {
        Err(Error::Argument(format!(
            "{small_name} must be smaller than {big_name}, got {small} and {big}"
        )))
    }
}

/// Refuses a mesh whose vertex or face count (`None` = overflowed `usize`) does not fit the
/// `u32` indices of [`crate::TriMesh`].
fn fits(n_vertices: Option<usize>, n_faces: Option<usize>) -> Result<()> {
    let limit = u32::MAX as usize;
    match (n_vertices, n_faces) {
        (Some(v), Some(f)) if v <= limit && f <= limit => Ok(()),
        _ => Err(Error::Argument(format!(
            "the requested mesh is too large: at most {limit} vertices and faces"
        ))),
    }
}

#[cfg(test)]
pub(crate) mod checks {
    //! Assertions shared by the generators' tests.

    use crate::TriMesh;
    use std::collections::{HashMap, HashSet};

    /// V − E + F.
    pub fn euler_characteristic(m: &TriMesh) -> i64 {
        let mut edges = HashSet::new();
        for f in &m.faces {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        m.positions.len() as i64 - edges.len() as i64 + m.faces.len() as i64
    }

    /// Checks that the mesh is a consistently oriented manifold with every vertex used, and
    /// returns its number of boundary edges. Each directed edge must occur once; an edge
    /// whose reverse does not occur is a boundary edge.
    pub fn check_oriented_manifold(m: &TriMesh) -> usize {
        let mut directed = HashMap::new();
        let mut used = vec![false; m.positions.len()];
        for (i, f) in m.faces.iter().enumerate() {
            assert!(
                f[0] != f[1] && f[1] != f[2] && f[0] != f[2],
                "face {i} is degenerate"
            );
            for k in 0..3 {
                used[f[k] as usize] = true;
                let e = (f[k], f[(k + 1) % 3]);
                assert!(directed.insert(e, i).is_none(), "directed edge {e:?} twice");
            }
        }
        assert!(used.iter().all(|&u| u), "a vertex is not used by any face");
        directed
            .keys()
            .filter(|(a, b)| !directed.contains_key(&(*b, *a)))
            .count()
    }

    /// Checks that no two vertices coincide (to 1e-9).
    pub fn check_no_duplicate_vertices(m: &TriMesh) {
        let mut seen = HashSet::new();
        for (i, p) in m.positions.iter().enumerate() {
            let key = p.map(|c| (c * 1e9).round() as i64);
            assert!(
                seen.insert(key),
                "vertex {i} at {p:?} repeats an earlier one"
            );
        }
    }

    /// Twice the signed area of face `f` projected on the xy-plane.
    pub fn signed_area_xy(m: &TriMesh, f: usize) -> f64 {
        let [a, b, c] = m.corners(f);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    }

    /// The unnormalized normal (b−a)×(c−a) and the centroid of face `f`.
    pub fn normal_and_centroid(m: &TriMesh, f: usize) -> ([f64; 3], [f64; 3]) {
        let [a, b, c] = m.corners(f);
        let u: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
        let v: [f64; 3] = std::array::from_fn(|k| c[k] - a[k]);
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        (n, std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0))
    }

    /// Total 3D area.
    pub fn total_area(m: &TriMesh) -> f64 {
        (0..m.faces.len())
            .map(|f| {
                let (n, _) = normal_and_centroid(m, f);
                0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
            })
            .sum()
    }

    /// Planar mesh checks: z = 0 and every face counter-clockwise with a positive area.
    pub fn check_planar_ccw(m: &TriMesh) {
        assert!(m.positions.iter().all(|p| p[2] == 0.0));
        for f in 0..m.faces.len() {
            let a = signed_area_xy(m, f);
            assert!(a > 1e-12, "face {f} has signed area {a}");
        }
    }

    /// Relative closeness.
    pub fn assert_close(a: f64, b: f64, rel: f64) {
        assert!(
            (a - b).abs() <= rel * b.abs(),
            "{a} and {b} differ by more than {rel} relative"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameter_errors_are_arguments() {
        assert!(matches!(
            square_grid(0, 3, 1.0, 1.0),
            Err(Error::Argument(_))
        ));
        assert!(matches!(
            square_grid(3, 3, f64::NAN, 1.0),
            Err(Error::Argument(_))
        ));
        assert!(matches!(
            square_grid(3, 3, 1.0, -1.0),
            Err(Error::Argument(_))
        ));
        assert!(matches!(
            square_grid(usize::MAX, 2, 1.0, 1.0),
            Err(Error::Argument(_))
        ));
        assert!(matches!(icosphere(20), Err(Error::Argument(_))));
        match regular_polygon(2, 1) {
            Err(Error::Argument(msg)) => assert_eq!(msg, "sides must be at least 3, got 2"),
            other => panic!("{other:?}"),
        }
    }
}
