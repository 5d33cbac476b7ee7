//! Remeshing through a spherical map (SDEM paper §5.2) or an ellipsoidal one (EDEM paper §5):
//! near-uniform points on the unit sphere (a Fibonacci spiral) or the ellipsoid (the same
//! lattice spread evenly by the ellipsoid's area), their convex hull, and every point pulled
//! back onto the input surface through the inverse map. The points of an ellipsoid are handled
//! as their images on the unit sphere: the convex hull of the ellipsoid's points is the linear
//! image of theirs, and a ray from the centre meets a mapped face on the ellipsoid where its
//! image meets the face's image.

use super::Layout;
use crate::Result;
use crate::geometry::ellipsoid::Ellipsoid;
use crate::mesh::triangulate::spherical_delaunay;

/// `n` (at least 4) points spread evenly by area over `ellipsoid`, as their images on the unit
/// sphere ([`Ellipsoid::equal_area_points`]), and their convex hull, faces oriented outward
/// (like the input's on a spherical or ellipsoidal map).
pub fn layout_ellipsoid(ellipsoid: &Ellipsoid, n: usize) -> Result<Layout> {
    let points = ellipsoid.equal_area_points(n.max(4));
    let faces = spherical_delaunay(&points)?;
    Ok(Layout {
        fixed: vec![None; points.len()],
        domain: points,
        faces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TriMesh;
    use crate::generate;
    use crate::mesh::topology::topology;

    fn remesh_sphere(input: &TriMesh, mapped: &[[f64; 3]], n: usize) -> Result<TriMesh> {
        let area = crate::geometry::face_areas(&input.positions, &input.faces);
        super::super::remesh(input, &area, mapped, super::super::Target::Sphere, n)
    }

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
