//! Midpoint subdivision: every triangle split into four at the midpoints of its edges, a
//! midpoint shared by the faces of its edge. The surface keeps its shape (the new vertices lie
//! on the old edges) and its topology; only the triangles get finer, so a mesh of any size can
//! be made from a real one (`demkit subdivide`, the scale cases of `demkit bench`).

use super::TriMesh;
use super::topology::EdgeGroups;
use crate::{Error, Result};

/// One round of midpoint subdivision of `mesh`.
///
/// The input vertices keep their indices; the midpoints of the E edges follow them, in
/// increasing (smaller endpoint, larger endpoint) order, as [`crate::mesh::edges`] lists the
/// edges: V + E vertices. Face `f` = (a, b, c) becomes the faces 4f to 4f + 3:
/// (a, m_ab, m_ca), (m_ab, b, m_bc), (m_ca, m_bc, c) and (m_ab, m_bc, m_ca), oriented as `f`:
/// 4F faces and 2E + 3F edges, so the Euler characteristic V − E + F is kept, and so are the
/// boundary loops (each with twice its vertices). A midpoint is ½a + ½b, coordinate by
/// coordinate: the correctly rounded midpoint, which does not overflow.
///
/// Errors: a face index out of range or a face repeating a vertex ([`Error::InvalidMesh`],
/// naming the face); a result too large for `u32` indices ([`Error::Argument`]), refused before
/// anything is allocated for it.
pub fn subdivide(mesh: &TriMesh) -> Result<TriMesh> {
    subdivide_levels(mesh, 1)
}

/// `levels` rounds of [`subdivide`] (`levels` = 0 gives the mesh unchanged): 4^levels · F faces,
/// the descendants of input face `f` being the faces 4^levels · f to 4^levels · (f + 1) − 1.
///
/// Errors: those of [`subdivide`]; the face count is checked for all the rounds before the
/// first one starts.
pub fn subdivide_levels(mesh: &TriMesh, levels: usize) -> Result<TriMesh> {
    check_faces(mesh)?;
    subdivided_count(mesh.n_faces(), levels)?;
    let mut current = mesh.clone();
    for _ in 0..levels {
        current = one_round(&current)?;
    }
    Ok(current)
}

/// The population of the faces of [`subdivide_levels`]`(mesh, levels)` from that of the faces
/// of `mesh`: every face's value split in 4^levels equal parts, so the total is kept and every
/// part keeps its parent's density (the four parts of a face have equal areas).
///
/// Errors: a result too large for `u32` face indices ([`Error::Argument`]).
pub fn split_population(population: &[f64], levels: usize) -> Result<Vec<f64>> {
    let parts = subdivided_count(population.len(), levels)? / population.len().max(1);
    // 4^levels is a power of two: dividing by it is exact (short of underflow).
    let share = 0.25f64.powi(levels as i32);
    let mut out = Vec::with_capacity(population.len() * parts);
    for &p in population {
        out.extend(std::iter::repeat_n(p * share, parts));
    }
    Ok(out)
}

/// The number of faces after `levels` rounds, refused beyond `u32` indices.
fn subdivided_count(n_faces: usize, levels: usize) -> Result<usize> {
    let limit = u32::MAX as usize;
    let count = |l: usize| {
        u32::try_from(l)
            .ok()
            .and_then(|l| 4usize.checked_pow(l))
            .and_then(|p| p.checked_mul(n_faces))
            .filter(|&n| n <= limit)
    };
    count(levels).ok_or_else(|| {
        let most = (0..levels).take_while(|&l| count(l).is_some()).last();
        let most = most.map_or("none".to_string(), |l| l.to_string());
        Error::Argument(format!(
            "levels must be at most {most} for {n_faces} faces (at most {limit} faces after \
             subdividing), got {levels}"
        ))
    })
}

/// Refuses the faces no subdivision can split: an index out of range or a repeated vertex.
fn check_faces(mesh: &TriMesh) -> Result<()> {
    let n = mesh.n_vertices();
    for (f, face) in mesh.faces.iter().enumerate() {
        if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
            return Err(Error::InvalidMesh(format!(
                "face {f} uses vertex {v}, but the mesh has {n} vertices"
            )));
        }
        let [a, b, c] = *face;
        if a == b || b == c || c == a {
            return Err(Error::InvalidMesh(format!(
                "face {f} repeats a vertex: {face:?}"
            )));
        }
    }
    Ok(())
}

/// One round on a mesh whose faces passed [`check_faces`] and whose 4F fits `u32`.
fn one_round(mesh: &TriMesh) -> Result<TriMesh> {
    let n = mesh.n_vertices();
    let groups = EdgeGroups::new(n, &mesh.faces);
    // The midpoint of every half-edge 3f + k (the edge from corner k to corner k + 1 of f).
    let mut midpoint = vec![0u32; 3 * mesh.n_faces()];
    let mut edges: Vec<[u32; 2]> = Vec::with_capacity(3 * mesh.n_faces() / 2 + 3);
    groups.for_each_edge(|lo, hi, half_edges| {
        let index = n + edges.len();
        for &h in half_edges {
            midpoint[h as usize] = index as u32;
        }
        edges.push([lo, hi]);
    });
    if n + edges.len() > u32::MAX as usize {
        return Err(Error::Argument(format!(
            "subdividing {n} vertices and {} edges gives too many vertices: at most {}",
            edges.len(),
            u32::MAX
        )));
    }
    let mut positions = Vec::with_capacity(n + edges.len());
    positions.extend_from_slice(&mesh.positions);
    positions.extend(edges.iter().map(|&[a, b]| {
        let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        std::array::from_fn(|k| 0.5 * p[k] + 0.5 * q[k])
    }));
    let mut faces = Vec::with_capacity(4 * mesh.n_faces());
    for (f, &[a, b, c]) in mesh.faces.iter().enumerate() {
        let [ab, bc, ca] = [midpoint[3 * f], midpoint[3 * f + 1], midpoint[3 * f + 2]];
        faces.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Ok(TriMesh::new(positions, faces))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{icosphere, regular_polygon, square_grid, torus};
    use crate::geometry::{face_areas, signed_area_2d};
    use crate::mesh::{edges, topology};

    #[test]
    fn a_triangle_becomes_four_with_its_midpoints_after_its_vertices() {
        let tri = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 2.0]],
            vec![[0, 1, 2]],
        );
        let s = subdivide(&tri).unwrap();
        // Edges in order (0,1), (0,2), (1,2): midpoints 3, 4, 5.
        assert_eq!(
            s.positions,
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 2.0, 2.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 1.0],
                [1.0, 1.0, 1.0],
            ]
        );
        assert_eq!(s.faces, vec![[0, 3, 4], [3, 1, 5], [4, 5, 2], [3, 5, 4]]);
    }

    #[test]
    fn counts_are_v_plus_e_and_four_f_and_the_topology_is_kept() {
        let meshes = [
            icosphere(2).unwrap(),
            torus(3.0, 1.0, 12, 6).unwrap(),
            regular_polygon(6, 3).unwrap(),
            square_grid(4, 3, 4.0, 3.0).unwrap(),
        ];
        for mesh in &meshes {
            let before = topology(mesh);
            let s = subdivide(mesh).unwrap();
            let after = topology(&s);
            assert_eq!(s.n_vertices(), mesh.n_vertices() + before.n_edges);
            assert_eq!(s.n_faces(), 4 * mesh.n_faces());
            assert_eq!(after.n_edges, 2 * before.n_edges + 3 * mesh.n_faces());
            assert_eq!(after.euler_characteristic, before.euler_characteristic);
            assert_eq!(after.genus, before.genus);
            assert_eq!(after.components, 1);
            assert_eq!(after.boundary_loops.len(), before.boundary_loops.len());
            for (l, m) in before.boundary_loops.iter().zip(&after.boundary_loops) {
                assert_eq!(m.len(), 2 * l.len());
            }
        }
    }

    #[test]
    fn midpoints_are_those_of_the_edges_in_order() {
        let mesh = torus(3.0, 1.0, 8, 5).unwrap();
        let s = subdivide(&mesh).unwrap();
        let n = mesh.n_vertices();
        assert_eq!(s.positions[..n], mesh.positions[..]);
        for (k, [a, b]) in edges(&mesh.faces).into_iter().enumerate() {
            let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
            let m: [f64; 3] = std::array::from_fn(|i| (p[i] + q[i]) / 2.0);
            assert_eq!(s.positions[n + k], m, "edge {k} = ({a}, {b})");
        }
    }

    #[test]
    fn a_planar_mesh_keeps_its_area_exactly_and_its_orientation() {
        // Integer corners: every midpoint and area below is exact.
        let grid = square_grid(4, 3, 4.0, 3.0).unwrap();
        let parents = face_areas(&grid.positions, &grid.faces);
        let s = subdivide_levels(&grid, 2).unwrap();
        let areas = face_areas(&s.positions, &s.faces);
        assert_eq!(areas.iter().sum::<f64>(), 12.0);
        for (f, &parent) in parents.iter().enumerate() {
            for &a in &areas[16 * f..16 * (f + 1)] {
                assert_eq!(a, parent / 16.0, "a descendant of face {f}");
            }
        }
        for face in &s.faces {
            let [a, b, c] = face.map(|v| s.positions[v as usize]);
            assert!(signed_area_2d(a, b, c) > 0.0, "{face:?}");
        }
    }

    #[test]
    fn levels_repeat_the_round_and_zero_levels_change_nothing() {
        let mesh = icosphere(1).unwrap();
        let twice = subdivide(&subdivide(&mesh).unwrap()).unwrap();
        assert_eq!(subdivide_levels(&mesh, 2).unwrap(), twice);
        assert_eq!(subdivide_levels(&mesh, 0).unwrap(), mesh);
    }

    #[test]
    fn populations_are_split_in_equal_parts() {
        assert_eq!(
            split_population(&[4.0, 8.0], 1).unwrap(),
            vec![1.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0]
        );
        let split = split_population(&[3.0, 0.1], 2).unwrap();
        assert_eq!(split.len(), 32);
        assert!(split[..16].iter().all(|&p| p == 3.0 / 16.0));
        assert!(split[16..].iter().all(|&p| p == 0.1 / 16.0));
        assert_eq!(split_population(&[5.0], 0).unwrap(), vec![5.0]);
    }

    #[test]
    fn faces_that_cannot_be_split_are_named() {
        let out_of_range = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 3]]);
        match subdivide(&out_of_range) {
            Err(Error::InvalidMesh(m)) => assert!(m.contains("face 0 uses vertex 3"), "{m}"),
            other => panic!("{other:?}"),
        }
        let repeated = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 2], [2, 1, 2]]);
        match subdivide(&repeated) {
            Err(Error::InvalidMesh(m)) => assert!(m.contains("face 1 repeats"), "{m}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn too_many_faces_are_refused_before_any_work() {
        let tri = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        );
        // 4^16 = 2^32 faces: one more than u32 holds.
        for levels in [16, 40, usize::MAX] {
            assert!(matches!(
                subdivide_levels(&tri, levels),
                Err(Error::Argument(_))
            ));
            assert!(matches!(
                split_population(&[1.0], levels),
                Err(Error::Argument(_))
            ));
        }
        assert_eq!(subdivided_count(1, 15).unwrap(), 1 << 30);
        match subdivided_count(96_970, 8) {
            Err(Error::Argument(m)) => assert!(m.starts_with("levels must be at most 7 "), "{m}"),
            other => panic!("{other:?}"),
        }
    }
}
