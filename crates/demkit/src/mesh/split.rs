//! Splitting chosen edges of a mesh at their midpoints (red–green refinement of the faces
//! they bound).

use super::TriMesh;
use crate::geometry::face_areas;
use std::collections::{HashMap, HashSet};

/// A mesh refined by [`split_edges`], and where its faces came from.
///
/// The input vertices keep their indices; the midpoints follow them. Every input face `f`
/// keeps index `f` for its first part; its other parts are appended after the input faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Refinement {
    /// The refined mesh.
    pub mesh: TriMesh,
    /// For every face of `mesh`, the input face it is part of.
    pub parent_face: Vec<usize>,
}

impl Refinement {
    /// Shares every input face's value of `population` among its parts in proportion to their
    /// area on the surface, so that each part keeps its parent's density.
    pub fn population(&self, population: &[f64]) -> Vec<f64> {
        let areas = face_areas(&self.mesh.positions, &self.mesh.faces);
        let mut parent_area = vec![0.0; population.len()];
        let mut parts = vec![0usize; population.len()];
        for (&p, &a) in self.parent_face.iter().zip(&areas) {
            parent_area[p] += a;
            parts[p] += 1;
        }
        self.parent_face
            .iter()
            .zip(&areas)
            .map(|(&p, &a)| {
                if parent_area[p] > 0.0 {
                    population[p] * a / parent_area[p]
                } else {
                    population[p] / parts[p] as f64
                }
            })
            .collect()
    }
}

/// Splits every edge of `edges` (vertex pairs, either order; pairs that are not edges of
/// `mesh` are ignored) at its midpoint; the midpoints are numbered in the order the faces
/// first meet them. A face with one split edge becomes two triangles,
/// with two it becomes three (the shorter diagonal of the quadrilateral left), with three
/// four; orientation is kept.
pub fn split_edges(mesh: &TriMesh, edges: &[[u32; 2]]) -> Refinement {
    let wanted: HashSet<(u32, u32)> = edges.iter().map(|&[a, b]| (a.min(b), a.max(b))).collect();
    let mut positions = mesh.positions.clone();
    let mut midpoint: HashMap<(u32, u32), u32> = HashMap::with_capacity(wanted.len());
    let mut faces = mesh.faces.clone();
    let mut parent_face: Vec<usize> = (0..faces.len()).collect();
    for (f, &face) in mesh.faces.iter().enumerate() {
        let m = [0, 1, 2].map(|k| {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            if !wanted.contains(&key) {
                return None;
            }
            Some(*midpoint.entry(key).or_insert_with(|| {
                let (pa, pb) = (positions[a as usize], positions[b as usize]);
                positions.push([
                    0.5 * (pa[0] + pb[0]),
                    0.5 * (pa[1] + pb[1]),
                    0.5 * (pa[2] + pb[2]),
                ]);
                (positions.len() - 1) as u32
            }))
        });
        let parts = split_face(face, m, &positions);
        faces[f] = parts[0];
        for &part in &parts[1..] {
            faces.push(part);
            parent_face.push(f);
        }
    }
    Refinement {
        mesh: TriMesh::new(positions, faces),
        parent_face,
    }
}

/// The parts of `face` = (v0, v1, v2) whose edge (v_k, v_k+1) has midpoint `m[k]` where split.
fn split_face(face: [u32; 3], m: [Option<u32>; 3], positions: &[[f64; 3]]) -> Vec<[u32; 3]> {
    let split = m.iter().filter(|x| x.is_some()).count();
    // Rotate so that the pattern starts at k: (a, b, c) = (v_k, v_k+1, v_k+2).
    let rotated = |k: usize| {
        (
            [face[k], face[(k + 1) % 3], face[(k + 2) % 3]],
            [m[k], m[(k + 1) % 3], m[(k + 2) % 3]],
        )
    };
    match split {
        0 => vec![face],
        1 => {
            let k = (0..3).find(|&k| m[k].is_some()).unwrap_or(0);
            let ([a, b, c], [mab, ..]) = rotated(k);
            let mab = mab.unwrap_or(a);
            vec![[a, mab, c], [mab, b, c]]
        }
        2 => {
            // The unsplit edge is (c, a): k is the edge after it.
            let k = (0..3).find(|&k| m[(k + 2) % 3].is_none()).unwrap_or(0);
            let ([a, b, c], [mab, mbc, _]) = rotated(k);
            let (mab, mbc) = (mab.unwrap_or(a), mbc.unwrap_or(b));
            let dist = |p: u32, q: u32| {
                let (p, q) = (positions[p as usize], positions[q as usize]);
                (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)
            };
            if dist(a, mbc) <= dist(c, mab) {
                vec![[mab, b, mbc], [a, mab, mbc], [a, mbc, c]]
            } else {
                vec![[mab, b, mbc], [a, mab, c], [mab, mbc, c]]
            }
        }
        _ => {
            let [a, b, c] = face;
            let [mab, mbc, mca] = m.map(|x| x.unwrap_or(a));
            vec![[a, mab, mca], [mab, b, mbc], [mca, mbc, c], [mab, mbc, mca]]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::signed_area_2d;

    use crate::generate_fixtures::unit_square as square;

    fn assert_positive(mesh: &TriMesh) {
        for f in &mesh.faces {
            let p = f.map(|v| mesh.positions[v as usize]);
            assert!(signed_area_2d(p[0], p[1], p[2]) > 0.0, "{f:?}");
        }
    }

    #[test]
    fn a_shared_edge_splits_both_faces_in_two() {
        let r = split_edges(&square(), &[[2, 0]]);
        assert_eq!(r.mesh.n_vertices(), 5);
        assert_eq!(r.mesh.positions[4], [0.5, 0.5, 0.0]);
        assert_eq!(r.mesh.n_faces(), 4);
        assert_eq!(r.parent_face, vec![0, 1, 0, 1]);
        assert_positive(&r.mesh);
        let total: f64 = face_areas(&r.mesh.positions, &r.mesh.faces).iter().sum();
        assert!((total - 1.0).abs() < 1e-15);
    }

    #[test]
    fn two_and_three_split_edges_give_three_and_four_parts_of_equal_total_area() {
        let tri = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.3, 1.0, 0.0]],
            vec![[0, 1, 2]],
        );
        for (edges, parts) in [
            (vec![[0, 1], [1, 2]], 3),
            (vec![[1, 2], [2, 0]], 3),
            (vec![[2, 0], [0, 1]], 3),
            (vec![[0, 1], [1, 2], [2, 0]], 4),
        ] {
            let r = split_edges(&tri, &edges);
            assert_eq!(r.mesh.n_faces(), parts);
            assert_positive(&r.mesh);
            let total: f64 = face_areas(&r.mesh.positions, &r.mesh.faces).iter().sum();
            assert!((total - 1.0).abs() < 1e-14, "{total}");
        }
    }

    #[test]
    fn population_keeps_each_parent_density() {
        let r = split_edges(&square(), &[[0, 2], [0, 1]]);
        let pop = r.population(&[3.0, 1.0]);
        let areas = face_areas(&r.mesh.positions, &r.mesh.faces);
        for ((&p, &a), &f) in pop.iter().zip(&areas).zip(&r.parent_face) {
            let density = [3.0, 1.0][f] / 0.5;
            assert!((p / a - density).abs() < 1e-12);
        }
        assert!((pop.iter().sum::<f64>() - 4.0).abs() < 1e-12);
    }

    #[test]
    fn pairs_that_are_not_edges_change_nothing() {
        let r = split_edges(&square(), &[[1, 3]]);
        assert_eq!(r.mesh, square());
    }
}
