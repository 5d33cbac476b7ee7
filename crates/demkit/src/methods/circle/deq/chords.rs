//! Chords of the holes: interior edges whose two ends lie on the same hole.
//!
//! On the hole's circle such an edge would be a chord, which lies inside the hole, so no circle
//! domain map of the mesh as given exists. Holes cut out of a scan by removing faces leave
//! them along their jagged rims: every *ear* (a triangle with two edges on a hole) and every
//! *peninsula* (a part of the surface joined to the rest by one edge whose ends are on the same
//! hole) has one. Splitting each chord at its midpoint ([`crate::mesh::split::split_edges`])
//! makes the map possible with every boundary vertex on its circle: the midpoint is an
//! interior vertex, free to lie outside the circle.

use std::collections::HashMap;

/// The chords of the holes `loops[1..]` (`loops[0]`, the outer loop, may have chords: they lie
/// inside the unit disk), each as a vertex pair, in the order the faces first meet them.
pub(crate) fn of_holes(n_vertices: usize, faces: &[[u32; 3]], loops: &[Vec<u32>]) -> Vec<[u32; 2]> {
    let mut hole_of = vec![0usize; n_vertices];
    for (h, lp) in loops.iter().enumerate().skip(1) {
        for &v in lp {
            hole_of[v as usize] = h;
        }
    }
    // Edges with both ends on the same hole, and how many faces each bounds.
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    let mut order = Vec::new();
    for face in faces {
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let h = hole_of[a as usize];
            if h != 0 && h == hole_of[b as usize] {
                let key = (a.min(b), a.max(b));
                let c = count.entry(key).or_insert(0);
                if *c == 0 {
                    order.push(key);
                }
                *c += 1;
            }
        }
    }
    order
        .into_iter()
        .filter(|key| count[key] == 2)
        .map(|(a, b)| [a, b])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology::topology;

    #[test]
    fn an_ear_on_a_hole_has_one_chord_and_the_outer_loop_none() {
        // A square annulus (outer 4×4, hole 2×2) plus an ear triangle glued inside the hole
        // on its bottom edge, joining hole vertices 4, 5 through a new apex 8.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 4.0, 0.0],
            [0.0, 4.0, 0.0],
            [1.0, 1.0, 0.0],
            [3.0, 1.0, 0.0],
            [3.0, 3.0, 0.0],
            [1.0, 3.0, 0.0],
            [2.0, 1.5, 0.0],
        ];
        let faces = vec![
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
            [4, 5, 8],
        ];
        let mesh = crate::TriMesh::new(positions, faces);
        let topo = topology(&mesh);
        let loops = crate::init::circle_domain::ordered_loops(&mesh, &topo.boundary_loops).unwrap();
        assert_eq!(loops.len(), 2);
        assert_eq!(of_holes(9, &mesh.faces, &loops), vec![[4, 5]]);
        // Without the ear the hole has no chord.
        let plain = &mesh.faces[..8];
        let loops = vec![vec![0, 1, 2, 3], vec![4, 7, 6, 5]];
        assert!(of_holes(9, plain, &loops).is_empty());
    }
}
