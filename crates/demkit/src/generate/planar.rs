//! Planar meshes with round boundaries: regular polygons, annuli, disks with circular holes.

use std::f64::consts::{PI, TAU};

use crate::mesh::triangulate::constrained_delaunay;

use super::{at_least, fits, positive, smaller};
use crate::{Error, Result, TriMesh};

/// A regular polygon with `sides` corners, circumradius 1, centred at the origin in the plane
/// z = 0, the first corner at (1, 0), triangulated by `rings` concentric rings — a subdivided
/// hexagon for `sides` = 6.
///
/// Vertex 0 is the centre. Ring k (1 ≤ k ≤ `rings`) is the polygon scaled by k/rings, with its
/// k·sides vertices equally spaced along its edges, counter-clockwise from the corner on the
/// positive x-axis; its vertices have indices from 1 + sides·k(k−1)/2 on. The strip between rings
/// k−1 and k has (2k−1)·sides faces, so there are 1 + sides·rings(rings+1)/2 vertices and
/// sides·rings² faces. For `sides` = 6 every face is an equilateral triangle of side 1/rings.
///
/// Errors: `sides` < 3, `rings` = 0.
pub fn regular_polygon(sides: usize, rings: usize) -> Result<TriMesh> {
    at_least("sides", sides, 3)?;
    at_least("rings", rings, 1)?;
    let ring_start = |k: usize| 1 + sides * k * (k - 1) / 2;
    let n_vertices = rings
        .checked_mul(rings + 1)
        .and_then(|r| r.checked_mul(sides))
        .map(|n| 1 + n / 2);
    let n_faces = rings.checked_mul(rings).and_then(|r| r.checked_mul(sides));
    fits(n_vertices, n_faces)?;

    let corner = |s: usize| {
        let t = TAU * (s % sides) as f64 / sides as f64;
        [t.cos(), t.sin()]
    };
    let mut positions = Vec::with_capacity(n_vertices.unwrap_or(0));
    positions.push([0.0, 0.0, 0.0]);
    for k in 1..=rings {
        let scale = k as f64 / rings as f64;
        for s in 0..sides {
            let (c0, c1) = (corner(s), corner(s + 1));
            for t in 0..k {
                let w = t as f64 / k as f64;
                positions.push([
                    scale * ((1.0 - w) * c0[0] + w * c1[0]),
                    scale * ((1.0 - w) * c0[1] + w * c1[1]),
                    0.0,
                ]);
            }
        }
    }

    // Vertex t (0 ≤ t ≤ k) of sector s on ring k; t = k is the next sector's corner.
    let on_ring = |k: usize, s: usize, t: usize| {
        if k == 0 {
            0
        } else {
            (ring_start(k) + (s * k + t) % (sides * k)) as u32
        }
    };
    let mut faces = Vec::with_capacity(n_faces.unwrap_or(0));
    for k in 1..=rings {
        for s in 0..sides {
            let inner = |t: usize| on_ring(k - 1, s, t);
            let outer = |t: usize| on_ring(k, s, t);
            for t in 0..k {
                faces.push([outer(t), outer(t + 1), inner(t)]);
                if t + 1 < k {
                    faces.push([inner(t), outer(t + 1), inner(t + 1)]);
                }
            }
        }
    }
    Ok(TriMesh::new(positions, faces))
}

/// The annulus `inner_r` ≤ |p| ≤ `outer_r` in the plane z = 0, on a polar grid: `n_radial` + 1
/// circles of radii equally spaced from `inner_r` to `outer_r`, each with `n_angular` vertices
/// at angles 2πj/n_angular (j = 0, 1, ...). Vertex (i, j) — circle i, angle j — has index
/// `i*n_angular + j`; each cell between circles i, i+1 and angles j, j+1 is split into two faces
/// along the same diagonal. (n_radial+1)·n_angular vertices, 2·n_radial·n_angular faces; the
/// mesh's area is that of the region between two regular n_angular-gons,
/// (n_angular/2)·sin(2π/n_angular)·(outer_r² − inner_r²).
///
/// Errors: radii not finite with 0 < inner_r < outer_r, `n_radial` = 0, `n_angular` < 3.
pub fn annulus(inner_r: f64, outer_r: f64, n_radial: usize, n_angular: usize) -> Result<TriMesh> {
    positive("inner_r", inner_r)?;
    positive("outer_r", outer_r)?;
    smaller(("inner_r", inner_r), ("outer_r", outer_r))?;
    at_least("n_radial", n_radial, 1)?;
    at_least("n_angular", n_angular, 3)?;
    let n_vertices = n_radial
        .checked_add(1)
        .and_then(|r| r.checked_mul(n_angular));
    let n_faces = n_radial
        .checked_mul(n_angular)
        .and_then(|c| c.checked_mul(2));
    fits(n_vertices, n_faces)?;

    let mut positions = Vec::with_capacity(n_vertices.unwrap_or(0));
    for i in 0..=n_radial {
        let t = i as f64 / n_radial as f64;
        let r = (1.0 - t) * inner_r + t * outer_r;
        for j in 0..n_angular {
            let a = TAU * j as f64 / n_angular as f64;
            positions.push([r * a.cos(), r * a.sin(), 0.0]);
        }
    }
    let index = |i: usize, j: usize| (i * n_angular + j % n_angular) as u32;
    let cells = (0..n_radial).flat_map(|i| (0..n_angular).map(move |j| (i, j)));
    let faces = super::split_cells(cells, index, n_faces.unwrap_or(0));
    Ok(TriMesh::new(positions, faces))
}

/// The unit disk minus circular holes `(cx, cy, r)`, in the plane z = 0: a constrained Delaunay
/// triangulation (spade) of
/// - the outer circle as a regular `resolution`-gon inscribed in the unit circle, vertex j at
///   angle 2πj/resolution — spacing h = 2π/resolution;
/// - each hole's circle as a regular m-gon inscribed in it, m = max(8, ⌈r·resolution⌉) (so its
///   spacing is about h), vertex j at
///   angle 2πj/m from its centre;
/// - interior points on a triangular lattice of spacing h through the origin (rows
///   y = k·h·√3/2, every other row shifted by h/2), keeping those at least h/2 inside the
///   outer circle and at least h/2 outside every hole;
///
/// with the polygons' edges as constraints, and the faces inside the holes dropped.
///
/// Vertices come in that order: the outer circle's `resolution`, then each hole's in turn,
/// then the lattice points row by row (bottom to top, left to right). The mesh has 1 + k
/// boundary loops (Euler characteristic 1 − k) and exactly the area of the outer polygon minus
/// the hole polygons. No randomness: the same arguments give the same mesh.
///
/// Errors: `resolution` < 8; a hole with a radius that is not positive and finite, or a
/// centre not finite; a hole not strictly inside the outer polygon (it must lie within distance
/// cos(π/resolution) of the origin); two holes that overlap or touch.
pub fn disk_with_holes(holes: &[(f64, f64, f64)], resolution: usize) -> Result<TriMesh> {
    at_least("resolution", resolution, 8)?;
    holed_domain(Outer::Disk, holes, resolution)
}

/// The largest ratio of a holed rectangle's sides: 1e100 failed to triangulate, 1e12 did not.
const MAX_ASPECT: f64 = 1e12;

/// The rectangle [−W/2, W/2] × [−H/2, H/2] minus circular holes `(cx, cy, r)` (z = 0), built
/// like [`disk_with_holes`]: the rectangle's sides split evenly with spacing about
/// h = max(W, H)/`resolution` (corners included), holes as m-gons with m = max(8, ⌈2πr/h⌉),
/// lattice points of spacing h at least h/2 from every boundary, constrained Delaunay.
///
/// Errors: `resolution` < 4; W or H not positive and finite; hole errors as for
/// [`disk_with_holes`] (a hole must lie strictly inside the rectangle); one side more than
/// 1e12 times the other.
pub fn rectangle_with_holes(
    width: f64,
    height: f64,
    holes: &[(f64, f64, f64)],
    resolution: usize,
) -> Result<TriMesh> {
    at_least("resolution", resolution, 4)?;
    positive("the width", width)?;
    positive("the height", height)?;
    if width.max(height) > MAX_ASPECT * width.min(height) {
        // The short side's vertices then coincide with the long side's in rounding.
        return Err(Error::Argument(format!(
            "the width and the height must be within a factor {MAX_ASPECT:e} of each other, \
             got {width:e} and {height:e}"
        )));
    }
    holed_domain(Outer::Rectangle(width, height), holes, resolution)
}

/// The outer boundary of a holed planar domain.
#[derive(Clone, Copy)]
enum Outer {
    /// The unit disk (a regular polygon of `resolution` sides).
    Disk,
    /// A centred W × H rectangle.
    Rectangle(f64, f64),
}

impl Outer {
    /// The boundary's vertices (counter-clockwise) and the lattice spacing.
    fn boundary(self, resolution: usize) -> (Vec<[f64; 2]>, f64) {
        match self {
            Outer::Disk => {
                let n = resolution;
                let pts = (0..n)
                    .map(|j| {
                        let a = TAU * j as f64 / n as f64;
                        [a.cos(), a.sin()]
                    })
                    .collect();
                (pts, TAU / n as f64)
            }
            Outer::Rectangle(w, h) => {
                let step = w.max(h) / resolution as f64;
                let (nx, ny) = (
                    ((w / step).round() as usize).max(1),
                    ((h / step).round() as usize).max(1),
                );
                let (x0, y0) = (-w / 2.0, -h / 2.0);
                let mut pts = Vec::with_capacity(2 * (nx + ny));
                for i in 0..nx {
                    pts.push([x0 + w * i as f64 / nx as f64, y0]);
                }
                for j in 0..ny {
                    pts.push([-x0, y0 + h * j as f64 / ny as f64]);
                }
                for i in 0..nx {
                    pts.push([-x0 - w * i as f64 / nx as f64, -y0]);
                }
                for j in 0..ny {
                    pts.push([x0, -y0 - h * j as f64 / ny as f64]);
                }
                (pts, step)
            }
        }
    }

    /// Signed distance from `p` to the boundary, positive inside.
    fn depth(self, p: [f64; 2], resolution: usize) -> f64 {
        match self {
            Outer::Disk => (PI / resolution as f64).cos() - p[0].hypot(p[1]),
            Outer::Rectangle(w, h) => (w / 2.0 - p[0].abs()).min(h / 2.0 - p[1].abs()),
        }
    }

    /// How far the boundary reaches from the origin (lattice extent).
    fn reach(self) -> f64 {
        match self {
            Outer::Disk => 1.0,
            Outer::Rectangle(w, h) => 0.5 * w.hypot(h),
        }
    }
}

fn holed_domain(outer: Outer, holes: &[(f64, f64, f64)], resolution: usize) -> Result<TriMesh> {
    let (outer_points, h) = outer.boundary(resolution);
    for (k, &(cx, cy, r)) in holes.iter().enumerate() {
        positive(&format!("the radius of hole {k}"), r)?;
        if !(cx.is_finite() && cy.is_finite()) {
            return Err(Error::Argument(format!(
                "the centre of hole {k} must be finite, got ({cx}, {cy})"
            )));
        }
        if matches!(outer, Outer::Disk) && cx.hypot(cy) + r >= 1.0 {
            return Err(Error::Argument(format!(
                "hole {k} (centre ({cx}, {cy}), radius {r}) is not inside the unit disk"
            )));
        }
        if outer.depth([cx, cy], resolution) <= r {
            return Err(Error::Argument(format!(
                "hole {k} (centre ({cx}, {cy}), radius {r}) reaches past the outer boundary at \
                 resolution {resolution}; increase the resolution or move the hole inwards"
            )));
        }
        for (l, &(dx, dy, s)) in holes.iter().enumerate().take(k) {
            if (cx - dx).hypot(cy - dy) <= r + s {
                return Err(Error::Argument(format!("holes {l} and {k} overlap")));
            }
        }
    }

    // Boundary loops: (first vertex, vertex count); loop 0 is the outer boundary.
    let mut points: Vec<[f64; 2]> = outer_points.iter().map(|p| [p[0], p[1]]).collect();
    let mut loops = vec![(0, points.len())];
    for &(cx, cy, r) in holes {
        let m = ((TAU * r / h).ceil() as usize).max(8);
        loops.push((points.len(), m));
        for j in 0..m {
            let a = TAU * j as f64 / m as f64;
            points.push([cx + r * a.cos(), cy + r * a.sin()]);
        }
    }
    let n_boundary = points.len();

    let margin = 0.5 * h;
    let row = h * 3f64.sqrt() / 2.0;
    let reach = outer.reach();
    let (rows, cols) = ((reach / row).ceil() as i64, (reach / h).ceil() as i64 + 1);
    for k in -rows..=rows {
        let shift = if k.rem_euclid(2) == 1 { 0.5 * h } else { 0.0 };
        for i in -cols..=cols {
            let (x, y) = (i as f64 * h + shift, k as f64 * row);
            let inside = outer.depth([x, y], resolution) >= margin
                && holes
                    .iter()
                    .all(|&(cx, cy, r)| (x - cx).hypot(y - cy) >= r + margin);
            if inside {
                points.push([x, y]);
            }
        }
    }
    fits(Some(points.len()), points.len().checked_mul(2))?;

    let mut edges = Vec::with_capacity(n_boundary);
    for &(start, m) in &loops {
        edges.extend((0..m).map(|j| [start + j, start + (j + 1) % m]));
    }
    let cdt = constrained_delaunay(&points, &edges).map_err(|_| {
        Error::Argument(
            "cannot triangulate the domain with holes: boundary vertices coincide or cross; \
             increase the resolution or separate the holes"
                .into(),
        )
    })?;

    // Which loop a vertex lies on (None for lattice points).
    let loop_of = |v: usize| loops.iter().position(|&(s, m)| v >= s && v < s + m);
    let faces: Vec<[u32; 3]> = cdt
        .faces
        .into_iter()
        .filter(|f| {
            // No vertex lies inside a hole, so a face inside a hole has all three corners on
            // that hole's (convex) polygon, and conversely.
            let v = f.map(|i| i as usize);
            let l = loop_of(v[0]);
            !(l.is_some_and(|l| l > 0) && l == loop_of(v[1]) && l == loop_of(v[2]))
        })
        .collect();
    let positions = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    Ok(TriMesh::new(positions, faces))
}

#[cfg(test)]
mod tests {
    use super::super::checks::*;
    use super::*;

    /// Area of a regular m-gon inscribed in a circle of radius r.
    fn polygon_area(m: usize, r: f64) -> f64 {
        0.5 * m as f64 * (TAU / m as f64).sin() * r * r
    }

    #[test]
    fn regular_polygon_counts_and_area() {
        for (sides, rings) in [(3, 1), (6, 1), (6, 4), (5, 3), (12, 7)] {
            let m = regular_polygon(sides, rings).unwrap();
            assert_eq!(m.n_vertices(), 1 + sides * rings * (rings + 1) / 2);
            assert_eq!(m.n_faces(), sides * rings * rings);
            check_planar_ccw(&m);
            check_no_duplicate_vertices(&m);
            assert_eq!(euler_characteristic(&m), 1);
            assert_eq!(check_oriented_manifold(&m), sides * rings);
            assert_close(total_area(&m), polygon_area(sides, 1.0), 1e-13);
            let r_max = m
                .positions
                .iter()
                .map(|p| p[0].hypot(p[1]))
                .fold(0.0, f64::max);
            assert_close(r_max, 1.0, 1e-15);
        }
    }

    #[test]
    fn subdivided_hexagon_is_equilateral() {
        // Every face of a subdivided hexagon is an equilateral triangle of side 1/rings.
        let m = regular_polygon(6, 3).unwrap();
        assert_eq!(m.positions[1], [1.0 / 3.0, 0.0, 0.0]);
        for f in 0..m.n_faces() {
            let c = m.corners(f);
            for k in 0..3 {
                let (p, q) = (c[k], c[(k + 1) % 3]);
                let len = (q[0] - p[0]).hypot(q[1] - p[1]);
                assert!((len - 1.0 / 3.0).abs() < 1e-14, "face {f}: {len}");
            }
        }
    }

    #[test]
    fn annulus_counts_and_area() {
        let m = annulus(0.5, 2.0, 4, 24).unwrap();
        assert_eq!(m.n_vertices(), 5 * 24);
        assert_eq!(m.n_faces(), 2 * 4 * 24);
        assert_eq!(m.positions[24], [0.875, 0.0, 0.0]);
        check_planar_ccw(&m);
        check_no_duplicate_vertices(&m);
        assert_eq!(euler_characteristic(&m), 0);
        assert_eq!(check_oriented_manifold(&m), 2 * 24);
        let want = polygon_area(24, 2.0) - polygon_area(24, 0.5);
        assert_close(total_area(&m), want, 1e-13);
        let fine = annulus(0.5, 2.0, 4, 720).unwrap();
        assert_close(total_area(&fine), PI * (4.0 - 0.25), 1e-4);
        assert!(matches!(annulus(2.0, 1.0, 1, 8), Err(Error::Argument(_))));
    }

    #[test]
    fn disk_without_holes() {
        let m = disk_with_holes(&[], 32).unwrap();
        check_planar_ccw(&m);
        check_no_duplicate_vertices(&m);
        assert_eq!(euler_characteristic(&m), 1);
        assert_eq!(check_oriented_manifold(&m), 32);
        assert_close(total_area(&m), polygon_area(32, 1.0), 1e-12);
        assert!(m.n_vertices() > 32 + 50, "{}", m.n_vertices());
    }

    #[test]
    fn disk_with_two_holes() {
        let holes = [(-0.4, 0.0, 0.25), (0.45, 0.1, 0.2)];
        let m = disk_with_holes(&holes, 64).unwrap();
        check_planar_ccw(&m);
        check_no_duplicate_vertices(&m);
        assert_eq!(euler_characteristic(&m), 1 - 2);
        let (m0, m1) = (16, 13); // ⌈0.25·64⌉, ⌈0.2·64⌉
        assert_eq!(check_oriented_manifold(&m), 64 + m0 + m1);
        let want = polygon_area(64, 1.0) - polygon_area(m0, 0.25) - polygon_area(m1, 0.2);
        assert_close(total_area(&m), want, 1e-12);
        // No face reaches into a hole.
        for f in 0..m.n_faces() {
            let c = m.corners(f);
            let centroid = [
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            ];
            for &(cx, cy, r) in &holes {
                let d = (centroid[0] - cx).hypot(centroid[1] - cy);
                assert!(d > r * (PI / m0.min(m1) as f64).cos() - 1e-12, "face {f}");
            }
        }
        // Deterministic.
        assert_eq!(disk_with_holes(&holes, 64).unwrap(), m);
    }

    #[test]
    fn disk_with_holes_refuses_bad_holes() {
        let err = |holes: &[(f64, f64, f64)], n| match disk_with_holes(holes, n) {
            Err(Error::Argument(msg)) => msg,
            other => panic!("{other:?}"),
        };
        assert!(err(&[(0.0, 0.0, 0.5), (0.2, 0.0, 0.5)], 32).contains("overlap"));
        assert!(err(&[(0.6, 0.0, 0.5)], 32).contains("not inside the unit disk"));
        assert!(err(&[(0.0, 0.0, 0.995)], 16).contains("increase the resolution"));
        assert!(err(&[(0.0, 0.0, 0.0)], 32).contains("radius of hole 0"));
        assert!(err(&[(f64::NAN, 0.0, 0.1)], 32).contains("centre of hole 0"));
        assert!(err(&[], 4).contains("resolution"));
    }
}
