//! Figures of a remeshed surface: how even its triangle areas are, how well shaped its
//! triangles are, and how far its vertices lie from the surface it was made from.

use crate::TriMesh;
use crate::geometry::grid::GridCells;
use crate::geometry::triangle_area;
use crate::geometry::{dot, norm, sub};

/// The shape figures of a triangle mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// Standard deviation over mean of the face areas.
    pub area_cv: f64,
    /// Median over the faces of each face's smallest angle, in degrees.
    pub median_min_angle_deg: f64,
    /// The smallest angle of all faces, in degrees.
    pub min_angle_deg: f64,
}

/// The [`Quality`] of `mesh` (NaN figures for a mesh without faces).
pub fn quality(mesh: &TriMesh) -> Quality {
    let areas: Vec<f64> = (0..mesh.n_faces())
        .map(|f| {
            let [a, b, c] = mesh.corners(f);
            triangle_area(a, b, c)
        })
        .collect();
    let n = areas.len() as f64;
    let mean = areas.iter().sum::<f64>() / n;
    let var = areas.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / n;
    let mut angles: Vec<f64> = (0..mesh.n_faces())
        .map(|f| smallest_angle(mesh.corners(f)))
        .collect();
    angles.sort_by(f64::total_cmp);
    Quality {
        area_cv: var.sqrt() / mean,
        median_min_angle_deg: crate::metrics::quantile(&angles, 0.5),
        min_angle_deg: angles.first().copied().unwrap_or(f64::NAN),
    }
}

/// The smallest interior angle of a triangle, in degrees.
pub fn smallest_angle(p: [[f64; 3]; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
            let c = dot(a, b) / (norm(a) * norm(b));
            c.clamp(-1.0, 1.0).acos().to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The largest distance from a point of `points` to the surface `surface` (each point's
/// distance to its nearest triangle). Distances up to `tol` are found through a grid of the
/// triangles' boxes grown by `tol`; a point farther than that is measured against every face.
pub fn max_distance_to_surface(points: &[[f64; 3]], surface: &TriMesh, tol: f64) -> f64 {
    let (lo, hi) = crate::geometry::bounding_box(&surface.positions);
    let (lo, hi) = (lo.map(|x| x - tol), hi.map(|x| x + tol));
    // About two faces per cell on average.
    let nf = surface.n_faces().max(1) as f64;
    let vol = (0..3).map(|d| (hi[d] - lo[d]).max(1e-300)).product::<f64>();
    let cell = (vol * 2.0 / nf).cbrt().max(1e-300);
    let dims = [0, 1, 2].map(|d| (((hi[d] - lo[d]) / cell).ceil() as usize).clamp(1, 512));
    let size = [0, 1, 2].map(|d| (hi[d] - lo[d]).max(1e-300) / dims[d] as f64);
    let cells = GridCells::new(lo, size, dims);
    // Each face in the cells its box, grown by `tol`, meets: a face within `tol` of a point is
    // listed in the point's cell.
    let grid = cells.bucket(surface.n_faces(), |f| {
        let c = surface.corners(f);
        Some((
            cells.cell_of([0, 1, 2].map(|d| c[0][d].min(c[1][d]).min(c[2][d]) - tol)),
            cells.cell_of([0, 1, 2].map(|d| c[0][d].max(c[1][d]).max(c[2][d]) + tol)),
        ))
    });
    let mut worst = 0.0f64;
    for &p in points {
        let inside_box = (0..3).all(|d| p[d] >= lo[d] && p[d] <= hi[d]);
        let mut d = f64::INFINITY;
        if inside_box {
            for &f in grid.at(cells.cell_of(p)) {
                d = d.min(point_triangle_distance(p, surface.corners(f as usize)));
            }
        }
        if d > tol {
            d = (0..surface.n_faces())
                .map(|f| point_triangle_distance(p, surface.corners(f)))
                .fold(f64::INFINITY, f64::min);
        }
        worst = worst.max(d);
    }
    worst
}

/// The distance from `p` to the triangle `t` (closest point by Voronoi regions of the
/// triangle's vertices, edges and face).
pub fn point_triangle_distance(p: [f64; 3], t: [[f64; 3]; 3]) -> f64 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return norm(ap);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return norm(bp);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return norm(sub(ap, [ab[0] * v, ab[1] * v, ab[2] * v]));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return norm(cp);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return norm(sub(ap, [ac[0] * w, ac[1] * w, ac[2] * w]));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        let bc = sub(c, b);
        return norm(sub(bp, [bc[0] * w, bc[1] * w, bc[2] * w]));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    let q = [0, 1, 2].map(|d| a[d] + ab[d] * v + ac[d] * w);
    norm(sub(p, q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_equilateral_pair_has_sixty_degrees_and_even_areas() {
        let h = 3f64.sqrt() / 2.0;
        let m = TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5, h, 0.0],
                [1.5, h, 0.0],
            ],
            vec![[0, 1, 2], [1, 3, 2]],
        );
        let q = quality(&m);
        assert!(q.area_cv.abs() < 1e-12);
        assert!((q.median_min_angle_deg - 60.0).abs() < 1e-9);
        assert!((smallest_angle([[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]) - 45.0).abs() < 1e-9);
    }

    #[test]
    fn distances_to_a_triangle_by_region() {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let cases = [
            ([0.2, 0.2, 0.5], 0.5),           // above the face
            ([-1.0, -1.0, 0.0], 2f64.sqrt()), // beyond vertex a
            ([0.5, -2.0, 0.0], 2.0),          // beyond edge ab
            ([1.0, 1.0, 0.0], 0.5f64.sqrt()), // beyond edge bc
            ([2.0, 0.0, 1.0], 2f64.sqrt()),   // beyond vertex b
        ];
        for (p, d) in cases {
            assert!((point_triangle_distance(p, t) - d).abs() < 1e-12, "{p:?}");
        }
        let m = TriMesh::new(t.to_vec(), vec![[0, 1, 2]]);
        let d = max_distance_to_surface(&[[0.1, 0.1, 0.0], [0.2, 0.2, 0.3]], &m, 1e-6);
        assert!((d - 0.3).abs() < 1e-12);
    }
}
