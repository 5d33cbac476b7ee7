//! Remeshing through a spherical map (SDEM paper §5.2): near-uniform points on the unit sphere
//! (a Fibonacci spiral), their Delaunay triangulation (the convex hull), and every point pulled
//! back onto the input surface through the inverse map.

use super::sampling::fibonacci_sphere;
use crate::geometry::locate::{SphericalLocator, interpolate};
use crate::mesh::triangulate::spherical_delaunay;
use crate::{Result, TriMesh};

/// A new closed genus-0 triangulation of `input` with `n` vertices, laid out uniformly on its
/// spherical map `mapped` (unit vectors); faces oriented outward like the input's on the sphere.
pub fn remesh_sphere(input: &TriMesh, mapped: &[[f64; 3]], n: usize) -> Result<TriMesh> {
    let points = fibonacci_sphere(n.max(4));
    let faces = spherical_delaunay(&points)?;
    let locator = SphericalLocator::new(mapped, &input.faces);
    let positions = points
        .iter()
        .map(|&p| match locator.locate(p) {
            Some(loc) => interpolate(&input.positions, input.faces[loc.face], loc.weights),
            // Only if the map leaves a gap (it covers the sphere when bijective): the input
            // vertex whose image is nearest.
            None => input.positions[nearest(mapped, p)],
        })
        .collect();
    Ok(TriMesh::new(positions, faces))
}

fn nearest(points: &[[f64; 3]], p: [f64; 3]) -> usize {
    let d2 = |q: &[f64; 3]| (0..3).map(|d| (q[d] - p[d]).powi(2)).sum::<f64>();
    (0..points.len())
        .min_by(|&a, &b| d2(&points[a]).total_cmp(&d2(&points[b])))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;
    use crate::mesh::topology::topology;

    #[test]
    fn an_ellipsoid_through_its_radial_map_stays_on_the_ellipsoid() {
        let sphere = generate::icosphere(3).unwrap();
        let mapped: Vec<[f64; 3]> = sphere.positions.clone();
        let stretch = [2.0, 1.0, 0.5];
        let ellipsoid = TriMesh::new(
            sphere
                .positions
                .iter()
                .map(|p| [0, 1, 2].map(|d| p[d] * stretch[d]))
                .collect(),
            sphere.faces.clone(),
        );
        let out = remesh_sphere(&ellipsoid, &mapped, 300).unwrap();
        let t = topology(&out);
        assert_eq!((t.n_vertices, t.boundary_loops.len(), t.genus), (300, 0, 0));
        // Inside the ellipsoid (on chords of it), never far inside.
        for p in &out.positions {
            let e: f64 = (0..3).map(|d| (p[d] / stretch[d]).powi(2)).sum();
            assert!(e <= 1.0 + 1e-9 && e > 0.95, "{e}");
        }
        // Outward orientation.
        let volume: f64 = out
            .faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| out.positions[v as usize]);
                crate::geometry::dot(a, crate::geometry::cross(b, c))
            })
            .sum();
        assert!(volume > 0.0);
    }
}
