//! Rectangular grids: the flat square grid and height fields over it.

use super::{at_least, fits, positive};
use crate::{Error, Result, TriMesh};

/// The number of squares per side for [`gaussian`] that gives the DEM paper's Gaussian surface
/// (10368 = 2·72² triangles).
pub const GAUSSIAN_PAPER_N: usize = 72;

/// The number of squares per side for [`peaks`] nearest the DEM paper's peaks surface: the paper
/// has about 4108 triangles, which is not 2n² for any n; 45 gives 4050 (44 gives 3872, 46 gives
/// 4232).
pub const PEAKS_PAPER_N: usize = 45;

/// A flat grid of `nx` × `ny` squares in the plane z = 0, each split into two triangles.
///
/// Vertex (i, j), for 0 ≤ i ≤ nx and 0 ≤ j ≤ ny, has index `j*(nx+1) + i` and position
/// `(i*width/nx, j*height/ny, 0)`; so there are (nx+1)(ny+1) vertices and 2·nx·ny faces.
/// Every square, with corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1), is split
/// along the same diagonal a–c into the faces `[a, b, c]` and `[a, c, d]` (counter-clockwise);
/// square (i, j) gives faces 2(j·nx + i) and 2(j·nx + i) + 1.
///
/// The DEM paper's grid {(x, y) ∈ Z² : 0 ≤ x, y ≤ 99} (its Table 4) is
/// `square_grid(99, 99, 99.0, 99.0)`: 100 × 100 points at the integers.
///
/// Errors: `nx` or `ny` zero, `width` or `height` not positive and finite.
pub fn square_grid(nx: usize, ny: usize, width: f64, height: f64) -> Result<TriMesh> {
    at_least("nx", nx, 1)?;
    at_least("ny", ny, 1)?;
    positive("width", width)?;
    positive("height", height)?;
    grid(nx, ny, |i, j| {
        Ok([
            i as f64 * width / nx as f64,
            j as f64 * height / ny as f64,
            0.0,
        ])
    })
}

/// The surface z = f(x, y) over the rectangle [x0, x1] × [y0, y1], sampled on a grid of
/// `n` × `n` squares laid out exactly as [`square_grid`]`(n, n, ...)`: vertex (i, j) sits at
/// x = x0 + (x1 − x0)·i/n, y = y0 + (y1 − y0)·j/n (computed so that both ends are exact).
///
/// Faces are counter-clockwise seen from +z (normals point up).
///
/// Errors: `n` zero, bounds not finite or not increasing, `f` not finite at a vertex.
pub fn height_field(
    n: usize,
    f: impl Fn(f64, f64) -> f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
) -> Result<TriMesh> {
    at_least("n", n, 1)?;
    for (name, lo, hi) in [("x", x0, x1), ("y", y0, y1)] {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(Error::Argument(format!(
                "the {name} range must be finite and increasing, got [{lo}, {hi}]"
            )));
        }
    }
    let lerp = |a: f64, b: f64, k: usize| {
        let t = k as f64 / n as f64;
        (1.0 - t) * a + t * b
    };
    grid(n, n, |i, j| {
        let (x, y) = (lerp(x0, x1, i), lerp(y0, y1, j));
        let z = f(x, y);
        if z.is_finite() {
            Ok([x, y, z])
        } else {
            Err(Error::Argument(format!(
                "the height function is {z} at ({x}, {y})"
            )))
        }
    })
}

/// MATLAB's `peaks` function:
/// z = 3(1−x)² e^(−x²−(y+1)²) − 10(x/5 − x³ − y⁵) e^(−x²−y²) − (1/3) e^(−(x+1)²−y²).
pub fn peaks_function(x: f64, y: f64) -> f64 {
    3.0 * (1.0 - x).powi(2) * (-x * x - (y + 1.0).powi(2)).exp()
        - 10.0 * (x / 5.0 - x.powi(3) - y.powi(5)) * (-x * x - y * y).exp()
        - (-(x + 1.0).powi(2) - y * y).exp() / 3.0
}

/// MATLAB's peaks surface ([`peaks_function`]) over [−3, 3]², as a [`height_field`] of `n` × `n`
/// squares: (n+1)² vertices, 2n² faces. [`PEAKS_PAPER_N`] = 45 (4050 faces) is the nearest grid
/// to the DEM paper's peaks mesh.
pub fn peaks(n: usize) -> Result<TriMesh> {
    height_field(n, peaks_function, -3.0, 3.0, -3.0, 3.0)
}

/// The Gaussian bump z = exp(−((x − 0.5)² + (y − 0.5)²) / 0.1): 1 at the centre,
/// e^(−5) ≈ 0.0067 at the corners of [0, 1]².
pub fn gaussian_function(x: f64, y: f64) -> f64 {
    (-((x - 0.5).powi(2) + (y - 0.5).powi(2)) / 0.1).exp()
}

/// The Gaussian surface ([`gaussian_function`]) over [0, 1]², as a [`height_field`] of `n` × `n`
/// squares: (n+1)² vertices, 2n² faces. [`GAUSSIAN_PAPER_N`] = 72 gives the DEM paper's
/// 10368 triangles.
pub fn gaussian(n: usize) -> Result<TriMesh> {
    height_field(n, gaussian_function, 0.0, 1.0, 0.0, 1.0)
}

/// The (nx+1) × (ny+1) grid with vertex (i, j) at `position(i, j)`, triangulated as described in
/// [`square_grid`].
fn grid(
    nx: usize,
    ny: usize,
    position: impl Fn(usize, usize) -> Result<[f64; 3]>,
) -> Result<TriMesh> {
    let n_vertices =
        (nx.checked_add(1)).and_then(|a| ny.checked_add(1).and_then(|b| a.checked_mul(b)));
    let n_faces = nx.checked_mul(ny).and_then(|s| s.checked_mul(2));
    fits(n_vertices, n_faces)?;
    let mut positions = Vec::with_capacity(n_vertices.unwrap_or(0));
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(position(i, j)?);
        }
    }
    let index = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let cells = (0..ny).flat_map(|j| (0..nx).map(move |i| (i, j)));
    let faces = super::split_cells(cells, index, n_faces.unwrap_or(0));
    Ok(TriMesh::new(positions, faces))
}

#[cfg(test)]
mod tests {
    use super::super::checks::*;
    use super::*;

    #[test]
    fn square_grid_layout() {
        let m = square_grid(3, 2, 6.0, 1.0).unwrap();
        assert_eq!(m.n_vertices(), 12);
        assert_eq!(m.n_faces(), 12);
        // Vertex (i, j) = (2, 1) has index 1*4 + 2 = 6 and position (4, 0.5, 0).
        assert_eq!(m.positions[6], [4.0, 0.5, 0.0]);
        assert_eq!(m.positions[11], [6.0, 1.0, 0.0]);
        // Square (1, 1): faces 2*(1*3+1) = 8 and 9, split along (1,1)-(2,2).
        assert_eq!(m.faces[8], [5, 6, 10]);
        assert_eq!(m.faces[9], [5, 10, 9]);
        check_planar_ccw(&m);
        check_no_duplicate_vertices(&m);
        assert_eq!(euler_characteristic(&m), 1);
        assert_eq!(check_oriented_manifold(&m), 2 * (3 + 2));
        assert_close(total_area(&m), 6.0, 1e-14);
    }

    #[test]
    fn square_grid_uses_one_diagonal() {
        let m = square_grid(4, 5, 4.0, 5.0).unwrap();
        for f in 0..m.n_faces() {
            let c = m.corners(f);
            // The one edge that is neither horizontal nor vertical goes up and to the right.
            let diagonals: Vec<_> = (0..3)
                .map(|k| {
                    let (p, q) = (c[k], c[(k + 1) % 3]);
                    (q[0] - p[0], q[1] - p[1])
                })
                .filter(|(dx, dy)| *dx != 0.0 && *dy != 0.0)
                .collect();
            assert_eq!(diagonals.len(), 1, "face {f}");
            assert!(diagonals[0].0 * diagonals[0].1 > 0.0, "face {f}");
        }
    }

    #[test]
    fn paper_grid_is_integer_points() {
        let m = square_grid(99, 99, 99.0, 99.0).unwrap();
        assert_eq!(m.n_vertices(), 100 * 100);
        assert_eq!(m.n_faces(), 2 * 99 * 99);
        for (k, p) in m.positions.iter().enumerate() {
            assert_eq!(*p, [(k % 100) as f64, (k / 100) as f64, 0.0]);
        }
    }

    #[test]
    fn tilted_plane_has_exact_area() {
        // z = 2x − y over [0, 1] × [0, 2]: area = sqrt(1 + 4 + 1) · 2.
        let m = height_field(7, |x, y| 2.0 * x - y, 0.0, 1.0, 0.0, 2.0).unwrap();
        assert_eq!(m.n_faces(), 2 * 49);
        assert_eq!(m.positions[63], [1.0, 2.0, 0.0]);
        assert_close(total_area(&m), 6f64.sqrt() * 2.0, 1e-13);
        for f in 0..m.n_faces() {
            assert!(signed_area_xy(&m, f) > 0.0);
        }
        check_no_duplicate_vertices(&m);
    }

    #[test]
    fn peaks_surface() {
        let m = peaks(PEAKS_PAPER_N).unwrap();
        assert_eq!(m.n_faces(), 4050);
        assert_eq!(m.n_vertices(), 46 * 46);
        assert_eq!(m.positions[0], [-3.0, -3.0, peaks_function(-3.0, -3.0)]);
        // peaks(0, 0) = 3/e − 1/(3e) = 8/(3e) (MATLAB: 0.9810).
        let m = peaks(4).unwrap();
        assert_eq!(m.positions[12][..2], [0.0, 0.0]);
        assert_close(m.positions[12][2], 8.0 / (3.0 * std::f64::consts::E), 1e-15);
        assert_close(
            peaks_function(1.0, 1.0),
            18.0 * (-2f64).exp() - (-5f64).exp() / 3.0,
            1e-14,
        );
        assert_eq!(euler_characteristic(&m), 1);
    }

    #[test]
    fn gaussian_surface() {
        let m = gaussian(GAUSSIAN_PAPER_N).unwrap();
        assert_eq!(m.n_faces(), 10368);
        let centre = 36 * 73 + 36;
        assert_eq!(m.positions[centre], [0.5, 0.5, 1.0]);
        assert_close(m.positions[0][2], (-5f64).exp(), 1e-15);
        // The area approaches ∫∫ sqrt(1 + |∇z|²) with |∇z| = 20·r·z (midpoint rule, 1000²).
        let k = 1000;
        let mut want = 0.0;
        for i in 0..k {
            for j in 0..k {
                let (x, y) = ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64);
                let r = (x - 0.5).hypot(y - 0.5);
                let g = 20.0 * r * gaussian_function(x, y);
                want += (1.0 + g * g).sqrt();
            }
        }
        want /= (k * k) as f64;
        let a = total_area(&m);
        assert_close(a, want, 5e-4);
        check_no_duplicate_vertices(&m);
    }

    #[test]
    fn height_field_errors() {
        assert!(matches!(
            height_field(3, |x, _| 1.0 / x, 0.0, 1.0, 0.0, 1.0),
            Err(Error::Argument(msg)) if msg == "the height function is inf at (0, 0)"
        ));
        assert!(matches!(
            height_field(3, |_, _| 0.0, 1.0, 1.0, 0.0, 1.0),
            Err(Error::Argument(_))
        ));
        assert!(matches!(gaussian(0), Err(Error::Argument(_))));
    }
}
