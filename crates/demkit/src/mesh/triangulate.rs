//! Triangulating point sets: constrained Delaunay triangulations in the plane (with optional
//! Delaunay refinement) and Delaunay triangulations of points on the unit sphere.
//!
//! The planar triangulations keep given segments as edges, which is how boundaries, holes and
//! region borders survive (remeshing: DEM paper §6.2, DEQ paper §7.1; cartograms: DEM paper
//! §6.1). On the sphere, the Delaunay triangulation of unit vectors is their convex hull
//! (SDEM paper §5.2). The triangulation itself is `spade`'s.

use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::geometry::sphere::{
    mat_vec, project_from_north, rotation_to_north, spherical_orientation,
};
use crate::{Error, Result};

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// A planar triangulation: points and counter-clockwise faces on them.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarTriangulation {
    /// The input points, in their order and at their indices, then any points the
    /// triangulation added (Steiner points of a refinement).
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise triangles.
    pub faces: Vec<[u32; 3]>,
}

/// How [`refined_constrained_delaunay`] refines (Ruppert-style Delaunay refinement).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refinement {
    /// Largest allowed triangle area (`None`: no area bound).
    pub max_area: Option<f64>,
    /// Smallest allowed interior angle in degrees (refinement is guaranteed to end below about
    /// 30°; 0 disables the angle bound).
    pub min_angle_deg: f64,
    /// At most this many points are added.
    pub max_added_points: usize,
}

impl Default for Refinement {
    fn default() -> Self {
        Refinement {
            max_area: None,
            min_angle_deg: 25.0,
            max_added_points: 1_000_000,
        }
    }
}

/// The constrained Delaunay triangulation of `points` in which every segment `[i, j]` is an
/// edge: all triangles of the convex hull, counter-clockwise; `points` keep their indices.
///
/// Errors ([`Error::InvalidMesh`]): a point that is not finite, two equal points, a segment
/// with an index out of range or joining a point to itself, two segments that cross or
/// overlap (segments may only share end points).
pub fn constrained_delaunay(
    points: &[[f64; 2]],
    segments: &[[usize; 2]],
) -> Result<PlanarTriangulation> {
    let cdt = build(points, segments)?;
    Ok(extract(&cdt, |_| true))
}

/// A refined constrained Delaunay triangulation of the region that the segments enclose: the
/// triangles with an odd winding number with respect to the segments (inside the outer loops,
/// outside their holes) are kept and refined until no angle is below
/// [`Refinement::min_angle_deg`] and no area above [`Refinement::max_area`]. Added points come
/// after the input points; a segment may be split by added points, and then the chain of its
/// pieces is in the triangulation instead. Faces are counter-clockwise.
///
/// Errors: those of [`constrained_delaunay`]; [`Error::InvalidMesh`] when the segments enclose
/// nothing; [`Error::Argument`] for a bad refinement setting.
pub fn refined_constrained_delaunay(
    points: &[[f64; 2]],
    segments: &[[usize; 2]],
    r: &Refinement,
) -> Result<PlanarTriangulation> {
    if !(r.min_angle_deg >= 0.0 && r.min_angle_deg < 35.0) {
        return Err(Error::Argument(format!(
            "the refinement's smallest angle must lie in [0°, 35°), got {}",
            r.min_angle_deg
        )));
    }
    if r.max_area.is_some_and(|a| !(a > 0.0 && a.is_finite())) {
        return Err(Error::Argument(
            "the refinement's largest area must be positive and finite".into(),
        ));
    }
    let mut cdt = build(points, segments)?;
    let mut params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(r.min_angle_deg))
        .with_max_additional_vertices(r.max_added_points);
    if let Some(a) = r.max_area {
        params = params.with_max_allowed_area(a);
    }
    let result = cdt.refine(params);
    let mut excluded = vec![false; cdt.num_all_faces()];
    for f in &result.excluded_faces {
        excluded[f.index()] = true;
    }
    let t = extract(&cdt, |f| !excluded[f]);
    if t.faces.is_empty() {
        return Err(Error::InvalidMesh(
            "the boundary segments enclose no area to triangulate".into(),
        ));
    }
    Ok(t)
}

/// The faces whose centroid lies inside the region bounded by `loops` (closed polygons given
/// by point indices), by the even–odd rule: inside the outer loops and outside their holes.
pub fn faces_inside(
    points: &[[f64; 2]],
    faces: &[[u32; 3]],
    loops: &[Vec<usize>],
) -> Vec<[u32; 3]> {
    faces
        .iter()
        .filter(|f| {
            let c = f.iter().fold([0.0, 0.0], |s, &v| {
                let p = points[v as usize];
                [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]
            });
            inside_loops(points, loops, c)
        })
        .copied()
        .collect()
}

/// True when `c` lies inside the region bounded by `loops` (closed polygons of point indices)
/// by the even–odd rule.
pub fn inside_loops(points: &[[f64; 2]], loops: &[Vec<usize>], c: [f64; 2]) -> bool {
    loops.iter().filter(|l| crosses_odd(points, l, c)).count() % 2 == 1
}

/// True when a ray from `c` towards +x crosses the closed polygon `lp` an odd number of times.
fn crosses_odd(points: &[[f64; 2]], lp: &[usize], c: [f64; 2]) -> bool {
    let mut odd = false;
    for k in 0..lp.len() {
        let a = points[lp[k]];
        let b = points[lp[(k + 1) % lp.len()]];
        if (a[1] > c[1]) != (b[1] > c[1]) {
            let x = a[0] + (c[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x > c[0] {
                odd = !odd;
            }
        }
    }
    odd
}

/// The Delaunay triangulation of points on the unit sphere, i.e. their convex hull, with faces
/// oriented outward ((b − a) × (c − a) · (a + b + c) > 0): [`spherical_constrained_delaunay`]
/// without segments, seen from the first point.
///
/// Errors ([`Error::InvalidMesh`]): fewer than 4 points, a point that is not a finite unit
/// vector (within 1e-6), two equal points, all points on one circle.
pub fn spherical_delaunay(points: &[[f64; 3]]) -> Result<Vec<[u32; 3]>> {
    spherical_constrained_delaunay(points, &[], 0)
}

/// A triangulation of points on the unit sphere keeping every segment `[i, j]` as an edge,
/// faces oriented outward; without segments it is the Delaunay triangulation (the convex hull).
///
/// The points are seen from `points[pole]` (rotated to the north pole) by stereographic
/// projection, which maps circles on the sphere to circles in the plane, so the planar
/// constrained Delaunay triangulation of the others is the spherical one away from the pole;
/// the boundary of the projection is then closed by a fan of triangles at the pole. The pole
/// must not be an end of a segment, and a segment should be short enough for its projection
/// to follow the arc between its ends (split long arcs first).
///
/// Errors ([`Error::InvalidMesh`]): fewer than 4 points, a point that is not a finite unit
/// vector (within 1e-6), two equal points, all points on one circle, a segment at the pole or
/// crossing another.
pub fn spherical_constrained_delaunay(
    points: &[[f64; 3]],
    segments: &[[usize; 2]],
    pole: usize,
) -> Result<Vec<[u32; 3]>> {
    if points.len() < 4 {
        return Err(Error::InvalidMesh(format!(
            "a spherical triangulation needs at least 4 points, got {}",
            points.len()
        )));
    }
    for (i, p) in points.iter().enumerate() {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        if !((n - 1.0).abs() <= 1e-6) {
            return Err(Error::InvalidMesh(format!(
                "point {i} is not on the unit sphere (|p| = {n})"
            )));
        }
    }
    if pole >= points.len() || segments.iter().flatten().any(|&v| v == pole) {
        return Err(Error::InvalidMesh(format!(
            "the projection pole {pole} must be a point that no segment ends at"
        )));
    }
    // Planar index k is point k, or k + 1 from the pole on.
    let global = |k: usize| (if k < pole { k } else { k + 1 }) as u32;
    let local = |v: usize| if v < pole { v } else { v - 1 };
    let rot = rotation_to_north(points[pole]);
    let planar: Vec<[f64; 2]> = points
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != pole)
        .map(|(_, &p)| {
            let w = project_from_north(mat_vec(&rot, p));
            [w[0], w[1]]
        })
        .collect();
    let planar_segments: Vec<[usize; 2]> = segments.iter().map(|s| s.map(local)).collect();
    let t = constrained_delaunay(&planar, &planar_segments)?;
    if t.faces.is_empty() {
        return Err(Error::InvalidMesh(
            "the points on the sphere all lie on one circle".into(),
        ));
    }
    let mut faces: Vec<[u32; 3]> = t
        .faces
        .iter()
        .map(|f| f.map(|k| global(k as usize)))
        .collect();
    // The projection's boundary: directed edges of its (counter-clockwise) faces without their
    // reverse. The outer side of each, closed at the pole, is the counter-clockwise (b, a, pole).
    let mut directed = std::collections::HashSet::new();
    for f in &faces {
        for k in 0..3 {
            directed.insert((f[k], f[(k + 1) % 3]));
        }
    }
    let mut fan: Vec<[u32; 3]> = directed
        .iter()
        .filter(|&&(a, b)| !directed.contains(&(b, a)))
        .map(|&(a, b)| [b, a, pole as u32])
        .collect();
    fan.sort_unstable();
    faces.extend(fan);
    // Stereographic projection keeps or reverses every orientation at once: decide by the sum.
    let sum: f64 = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| points[v as usize]);
            spherical_orientation(a, b, c)
        })
        .sum();
    if sum < 0.0 {
        for f in &mut faces {
            f.swap(1, 2);
        }
    }
    Ok(faces)
}

/// Two points at exactly the same position (the first such pair in sorted order), if any.
pub(crate) fn coincident_pair(points: &[[f64; 2]]) -> Option<(usize, usize)> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_unstable_by(|&a, &b| {
        points[a][0]
            .total_cmp(&points[b][0])
            .then(points[a][1].total_cmp(&points[b][1]))
    });
    order
        .windows(2)
        .find(|w| points[w[0]] == points[w[1]])
        .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
}

/// Loads points and segments into a CDT, refusing what would make it differ from the input.
fn build(points: &[[f64; 2]], segments: &[[usize; 2]]) -> Result<Cdt> {
    if let Some(i) = points
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(Error::InvalidMesh(format!("point {i} is not finite")));
    }
    for (k, s) in segments.iter().enumerate() {
        if s[0] >= points.len() || s[1] >= points.len() || s[0] == s[1] {
            return Err(Error::InvalidMesh(format!(
                "segment {k} ({}, {}) does not join two of the {} points",
                s[0],
                s[1],
                points.len()
            )));
        }
    }
    let vertices: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let mut conflicts = 0usize;
    let cdt = Cdt::try_bulk_load_cdt(vertices, segments.to_vec(), |_| conflicts += 1)
        .map_err(|e| Error::InvalidMesh(format!("cannot triangulate the points: {e:?}")))?;
    if cdt.num_vertices() != points.len() {
        let (i, j) = coincident_pair(points).unwrap_or((0, 0));
        return Err(Error::InvalidMesh(format!(
            "points {i} and {j} to triangulate are at the same position ({}, {})",
            points[i][0], points[i][1]
        )));
    }
    let mut distinct: Vec<[usize; 2]> = segments
        .iter()
        .map(|s| [s[0].min(s[1]), s[0].max(s[1])])
        .collect();
    distinct.sort_unstable();
    distinct.dedup();
    if conflicts > 0 || cdt.num_constraints() != distinct.len() {
        return Err(Error::InvalidMesh(
            "segments cross, overlap or pass through other points".into(),
        ));
    }
    Ok(cdt)
}

/// The CDT's vertices by index and its inner faces (by face index) that `keep` accepts.
fn extract(cdt: &Cdt, keep: impl Fn(usize) -> bool) -> PlanarTriangulation {
    let points = cdt
        .vertices()
        .map(|v| {
            let p = v.position();
            [p.x, p.y]
        })
        .collect();
    let faces = cdt
        .inner_faces()
        .filter(|f| keep(f.fix().index()))
        .map(|f| f.vertices().map(|v| v.fix().index() as u32))
        .collect();
    PlanarTriangulation { points, faces }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::fibonacci_sphere;

    fn signed_area(p: &[[f64; 2]], f: [u32; 3]) -> f64 {
        let [a, b, c] = f.map(|v| p[v as usize]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    }

    fn total_area(t: &PlanarTriangulation) -> f64 {
        t.faces.iter().map(|&f| signed_area(&t.points, f)).sum()
    }

    fn has_edge(faces: &[[u32; 3]], a: u32, b: u32) -> bool {
        faces.iter().any(|f| {
            (0..3).any(|k| {
                let (p, q) = (f[k], f[(k + 1) % 3]);
                (p, q) == (a, b) || (p, q) == (b, a)
            })
        })
    }

    #[test]
    fn square_with_a_diagonal_segment_keeps_it() {
        let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        for diag in [[0, 2], [1, 3]] {
            let t = constrained_delaunay(&p, &[diag]).unwrap();
            assert_eq!(t.faces.len(), 2);
            assert!(has_edge(&t.faces, diag[0] as u32, diag[1] as u32));
            assert!(t.faces.iter().all(|&f| signed_area(&p, f) > 0.0));
            assert!((total_area(&t) - 1.0).abs() < 1e-15);
        }
    }

    /// The square [0, side]² with the hole [1, 2]², as points and segments.
    fn square_with_hole(side: f64) -> ([[f64; 2]; 8], [[usize; 2]; 8]) {
        let p = [
            [0.0, 0.0],
            [side, 0.0],
            [side, side],
            [0.0, side],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 2.0],
            [1.0, 2.0],
        ];
        (
            p,
            [
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 0],
                [4, 5],
                [5, 6],
                [6, 7],
                [7, 4],
            ],
        )
    }

    #[test]
    fn refinement_fills_a_square_with_a_hole_and_respects_the_area_bound() {
        // Outer square [0,4]², hole [1,2]² (clockwise or not does not matter: even-odd).
        let (p, seg) = square_with_hole(4.0);
        let r = Refinement {
            max_area: Some(0.05),
            ..Default::default()
        };
        let t = refined_constrained_delaunay(&p, &seg, &r).unwrap();
        assert!((total_area(&t) - 15.0).abs() < 1e-9, "{}", total_area(&t));
        assert!(t.faces.iter().all(|&f| signed_area(&t.points, f) > 0.0));
        assert!(
            t.faces
                .iter()
                .all(|&f| signed_area(&t.points, f) <= 0.05 + 1e-12)
        );
        assert_eq!(&t.points[..8], &p[..]);
    }

    #[test]
    fn faces_inside_drops_the_hole() {
        let (p, seg) = square_with_hole(3.0);
        let t = constrained_delaunay(&p, &seg).unwrap();
        assert!((total_area(&t) - 9.0).abs() < 1e-12);
        let inside = faces_inside(&t.points, &t.faces, &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]]);
        let a: f64 = inside.iter().map(|&f| signed_area(&p, f)).sum();
        assert!((a - 8.0).abs() < 1e-12, "{a}");
    }

    #[test]
    fn crossing_segments_and_duplicates_are_refused() {
        let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(constrained_delaunay(&p, &[[0, 2], [1, 3]]).is_err());
        assert!(constrained_delaunay(&p, &[[0, 4]]).is_err());
        let q = [[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]];
        assert!(constrained_delaunay(&q, &[]).is_err());
        let nan = [[0.0, f64::NAN], [1.0, 0.0], [0.0, 1.0]];
        assert!(constrained_delaunay(&nan, &[]).is_err());
    }

    #[test]
    fn octahedron_vertices_give_eight_outward_faces() {
        let p = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        // Cospherical points in degenerate position still give a closed, outward triangulation.
        let f = spherical_delaunay(&p).unwrap();
        assert_eq!(f.len(), 8);
        check_closed_outward(&p, &f);
    }

    #[test]
    fn fibonacci_points_give_a_closed_genus_zero_triangulation() {
        let n = 500;
        let p = fibonacci_sphere(n);
        let f = spherical_delaunay(&p).unwrap();
        assert_eq!(f.len(), 2 * n - 4);
        check_closed_outward(&p, &f);
    }

    #[test]
    fn a_segment_on_the_sphere_becomes_an_edge() {
        let n = 400;
        let mut p = fibonacci_sphere(n);
        // Two points on the equator a short arc apart, joined by a segment, and the pole the
        // triangulation is seen from: the north pole, added last.
        let e = |t: f64| [t.cos(), t.sin(), 0.0];
        p.push(e(0.0));
        p.push(e(0.25));
        p.push([0.0, 0.0, 1.0]);
        let f = spherical_constrained_delaunay(&p, &[[n, n + 1]], n + 2).unwrap();
        check_closed_outward(&p, &f);
        assert!(f.iter().any(|t| {
            (0..3).any(|k| {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                (a, b) == (n, n + 1) || (a, b) == (n + 1, n)
            })
        }));
        assert!(spherical_constrained_delaunay(&p, &[[n, n + 2]], n + 2).is_err());
    }

    /// Euler characteristic 2, every edge in exactly two faces with opposite directions, and
    /// outward orientation.
    fn check_closed_outward(p: &[[f64; 3]], f: &[[u32; 3]]) {
        let mut directed = std::collections::HashSet::new();
        for t in f {
            for k in 0..3 {
                assert!(directed.insert((t[k], t[(k + 1) % 3])), "edge used twice");
            }
            let [a, b, c] = t.map(|v| p[v as usize]);
            assert!(spherical_orientation(a, b, c) > 0.0);
        }
        for &(a, b) in &directed {
            assert!(directed.contains(&(b, a)), "open edge {a}-{b}");
        }
        let e = directed.len() / 2;
        assert_eq!(p.len() as i64 - e as i64 + f.len() as i64, 2);
    }
}
