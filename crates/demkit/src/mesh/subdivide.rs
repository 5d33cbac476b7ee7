//! Regular subdivision: every edge cut into K equal parts and every triangle into K² (K = 2:
//! midpoint subdivision, every triangle split into four at the midpoints of its edges). The
//! points on an edge are shared by the faces of that edge. The surface keeps its shape (the
//! new vertices lie on the old triangles) and its topology; only the triangles get finer, so a
//! mesh of any size can be made from a real one (`demkit subdivide`, the scale cases of
//! `demkit bench`).

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
    subdivide_parts(mesh, 2, levels)
}

/// `levels` rounds of regular subdivision in `parts` (K ≥ 1): every edge cut into K equal
/// parts, every face into K² faces of equal area; K = 2 is [`subdivide`].
///
/// In one round the input vertices keep their indices; the K − 1 points of each of the E
/// edges follow them, edge by edge in increasing (smaller endpoint, larger endpoint) order and
/// along each edge from its smaller endpoint; then the (K − 1)(K − 2)/2 interior points of
/// each face, face by face. In face `f` = (a, b, c) the point of barycentric lattice
/// coordinates (i, j), i + j ≤ K, is ((K − i − j) a + i b + j c) / K, computed coordinate by
/// coordinate as a·((K − i − j)/K) + b·(i/K) + c·(j/K); its faces K²f to K²(f + 1) − 1 are
/// the upward triangles (i, j), (i + 1, j), (i, j + 1) row by row (j = 0 first, i increasing),
/// then the downward ones (i + 1, j), (i + 1, j + 1), (i, j + 1) in the same order, all
/// oriented as `f`. For K = 2 this is the midpoint subdivision of [`subdivide`].
///
/// Errors: `parts` = 0 ([`Error::Argument`]); otherwise those of [`subdivide_levels`].
pub fn subdivide_parts(mesh: &TriMesh, parts: usize, levels: usize) -> Result<TriMesh> {
    check_faces(mesh)?;
    subdivided_count(mesh.n_faces(), parts, levels)?;
    let mut current = mesh.clone();
    for _ in 0..levels {
        current = one_round(&current, parts)?;
    }
    Ok(current)
}

/// The population of the faces of [`subdivide_levels`]`(mesh, levels)` from that of the faces
/// of `mesh`: every face's value split in 4^levels equal parts, so the total is kept and every
/// part keeps its parent's density (the four parts of a face have equal areas).
///
/// Errors: a result too large for `u32` face indices ([`Error::Argument`]).
pub fn split_population(population: &[f64], levels: usize) -> Result<Vec<f64>> {
    split_population_parts(population, 2, levels)
}

/// The population of the faces of [`subdivide_parts`]`(mesh, parts, levels)`: every face's
/// value split in (K²)^levels equal parts (exactly when K is a power of two; otherwise each
/// part is rounded once).
///
/// Errors: as [`subdivide_parts`].
pub fn split_population_parts(population: &[f64], parts: usize, levels: usize) -> Result<Vec<f64>> {
    let count = subdivided_count(population.len(), parts, levels)? / population.len().max(1);
    let share = 1.0 / count as f64;
    let mut out = Vec::with_capacity(population.len() * count);
    for &p in population {
        out.extend(std::iter::repeat_n(p * share, count));
    }
    Ok(out)
}

/// The number of faces after `levels` rounds in `parts`, refused beyond `u32` indices.
fn subdivided_count(n_faces: usize, parts: usize, levels: usize) -> Result<usize> {
    if parts == 0 {
        return Err(Error::Argument(
            "parts must be at least 1 (1 leaves the mesh as it is)".into(),
        ));
    }
    let limit = u32::MAX as usize;
    let count = |l: usize| {
        u32::try_from(l)
            .ok()
            .and_then(|l| parts.checked_mul(parts)?.checked_pow(l))
            .and_then(|p| p.checked_mul(n_faces))
            .filter(|&n| n <= limit)
    };
    count(levels).ok_or_else(|| {
        let most = (0..levels).take_while(|&l| count(l).is_some()).last();
        let most = most.map_or("none".to_string(), |l| l.to_string());
        Error::Argument(format!(
            "levels must be at most {most} for {n_faces} faces in {parts} parts (at most \
             {limit} faces after subdividing), got {levels}"
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

/// One round in `parts` on a mesh whose faces passed [`check_faces`] and whose K²F fits `u32`.
fn one_round(mesh: &TriMesh, parts: usize) -> Result<TriMesh> {
    let n = mesh.n_vertices();
    let k = parts as u32;
    let groups = EdgeGroups::new(n, &mesh.faces);
    // For every half-edge 3f + c (from corner c to corner c + 1 of f): its edge's first
    // point, and whether it runs from the edge's smaller endpoint.
    let mut first = vec![0u32; 3 * mesh.n_faces()];
    let mut forward = vec![true; 3 * mesh.n_faces()];
    let mut edges: Vec<[u32; 2]> = Vec::with_capacity(3 * mesh.n_faces() / 2 + 3);
    groups.for_each_edge(|lo, hi, half_edges| {
        let index = n + edges.len() * (parts - 1);
        for &h in half_edges {
            first[h as usize] = index as u32;
            let (f, c) = (h as usize / 3, h as usize % 3);
            forward[h as usize] = mesh.faces[f][c] == lo;
        }
        edges.push([lo, hi]);
    });
    let interior = (parts.saturating_sub(1)) * (parts.saturating_sub(2)) / 2;
    let total = n + edges.len() * (parts - 1) + mesh.n_faces() * interior;
    if total > u32::MAX as usize {
        return Err(Error::Argument(format!(
            "subdividing {n} vertices, {} edges and {} faces in {parts} parts gives {total} \
             vertices: at most {}",
            edges.len(),
            mesh.n_faces(),
            u32::MAX
        )));
    }
    let kf = parts as f64;
    let mix = |w: [u32; 3], p: [[f64; 3]; 3]| -> [f64; 3] {
        let w = w.map(|x| x as f64 / kf);
        std::array::from_fn(|c| w[0] * p[0][c] + w[1] * p[1][c] + w[2] * p[2][c])
    };
    let mut positions = Vec::with_capacity(total);
    positions.extend_from_slice(&mesh.positions);
    for &[a, b] in &edges {
        let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        positions.extend((1..k).map(|m| {
            let (wp, wq) = ((k - m) as f64 / kf, m as f64 / kf);
            std::array::from_fn(|c| wp * p[c] + wq * q[c])
        }));
    }
    let corners = |f: usize| mesh.faces[f].map(|v| mesh.positions[v as usize]);
    for f in 0..mesh.n_faces() {
        let p = corners(f);
        for j in 1..k {
            for i in 1..k - j {
                positions.push(mix([k - i - j, i, j], p));
            }
        }
    }
    let interior_base = n + edges.len() * (parts - 1);
    let mut faces = Vec::with_capacity(parts * parts * mesh.n_faces());
    for (f, &[a, b, c]) in mesh.faces.iter().enumerate() {
        // The point m/K of the way along the side from corner s to corner s + 1 of f.
        let side = |s: usize, m: u32| -> u32 {
            let h = 3 * f + s;
            first[h] + if forward[h] { m - 1 } else { k - m - 1 }
        };
        let base = (interior_base + f * interior) as u32;
        let vertex = |i: u32, j: u32| -> u32 {
            match (i, j) {
                (0, 0) => a,
                (i, 0) if i == k => b,
                (0, j) if j == k => c,
                (i, 0) => side(0, i),
                (i, j) if i + j == k => side(1, j),
                (0, j) => side(2, k - j),
                // Interior rows j = 1.., each with i = 1..K − j − 1.
                (i, j) => base + (1..j).map(|r| k - r - 1).sum::<u32>() + (i - 1),
            }
        };
        for j in 0..k {
            for i in 0..k - j {
                faces.push([vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)]);
            }
        }
        for j in 0..k {
            for i in 0..(k - j).saturating_sub(1) {
                faces.push([vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)]);
            }
        }
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
        assert_eq!(subdivided_count(1, 2, 15).unwrap(), 1 << 30);
        assert_eq!(subdivided_count(34_144, 6, 1).unwrap(), 1_229_184);
        assert!(matches!(
            subdivide_parts(&tri, 0, 1),
            Err(Error::Argument(_))
        ));
        match subdivided_count(96_970, 2, 8) {
            Err(Error::Argument(m)) => assert!(m.starts_with("levels must be at most 7 "), "{m}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_triangle_in_three_parts_has_its_lattice_points_and_nine_faces() {
        let tri = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 3.0, 0.0]],
            vec![[0, 1, 2]],
        );
        let s = subdivide_parts(&tri, 3, 1).unwrap();
        // Edges (0,1), (0,2), (1,2), two points each from the smaller end; one interior point.
        assert_eq!(
            s.positions,
            vec![
                [0.0, 0.0, 0.0],
                [3.0, 0.0, 0.0],
                [0.0, 3.0, 0.0],
                [1.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 2.0, 0.0],
                [2.0, 1.0, 0.0],
                [1.0, 2.0, 0.0],
                [1.0, 1.0, 0.0],
            ]
        );
        assert_eq!(s.n_faces(), 9);
        let area = face_areas(&s.positions, &s.faces);
        assert!(area.iter().all(|&a| (a - 0.5).abs() < 1e-15), "{area:?}");
        for face in &s.faces {
            let [a, b, c] = face.map(|v| s.positions[v as usize]);
            assert!(signed_area_2d(a, b, c) > 0.0, "{face:?}");
        }
        assert_eq!(topology(&s).n_edges, 18);
    }

    #[test]
    fn two_parts_is_the_midpoint_subdivision_and_one_part_changes_nothing() {
        let mesh = torus(3.0, 1.0, 8, 5).unwrap();
        assert_eq!(
            subdivide_parts(&mesh, 2, 2).unwrap(),
            subdivide_levels(&mesh, 2).unwrap()
        );
        assert_eq!(subdivide_parts(&mesh, 1, 3).unwrap(), mesh);
    }

    #[test]
    fn k_parts_give_the_lattice_counts_and_keep_the_topology() {
        let meshes = [
            icosphere(1).unwrap(),
            torus(3.0, 1.0, 10, 6).unwrap(),
            regular_polygon(5, 2).unwrap(),
        ];
        for mesh in &meshes {
            let before = topology(mesh);
            for k in [3usize, 4, 5] {
                let s = subdivide_parts(mesh, k, 1).unwrap();
                let after = topology(&s);
                let (v, e, f) = (mesh.n_vertices(), before.n_edges, mesh.n_faces());
                assert_eq!(s.n_vertices(), v + e * (k - 1) + f * (k - 1) * (k - 2) / 2);
                assert_eq!(s.n_faces(), k * k * f);
                assert_eq!(after.euler_characteristic, before.euler_characteristic);
                assert_eq!(after.genus, before.genus);
                assert_eq!(after.components, 1);
                assert_eq!(after.boundary_loops.len(), before.boundary_loops.len());
                for (l, m) in before.boundary_loops.iter().zip(&after.boundary_loops) {
                    assert_eq!(m.len(), k * l.len());
                }
                // Every child of a face has 1/K² of its area.
                let (a0, a1) = (
                    face_areas(&mesh.positions, &mesh.faces),
                    face_areas(&s.positions, &s.faces),
                );
                for (p, children) in a0.iter().zip(a1.chunks(k * k)) {
                    for c in children {
                        assert!((c * (k * k) as f64 - p).abs() < 1e-12 * p.max(1.0));
                    }
                }
            }
        }
    }

    #[test]
    fn populations_split_in_k_squared_parts() {
        let split = split_population_parts(&[9.0, 18.0], 3, 1).unwrap();
        assert_eq!(split.len(), 18);
        assert!(split[..9].iter().all(|&p| (p - 1.0).abs() < 1e-15));
        assert!(split[9..].iter().all(|&p| (p - 2.0).abs() < 1e-15));
        assert_eq!(
            split_population_parts(&[3.0], 2, 2).unwrap(),
            split_population(&[3.0], 2).unwrap()
        );
    }
}
