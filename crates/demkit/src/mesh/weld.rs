//! Welding: merging vertices that share a position (exactly, or within a tolerance).
//!
//! Formats that store every triangle separately (STL) repeat each vertex once per incident face;
//! welding restores the shared vertices the topology needs.

use super::TriMesh;
use std::collections::HashMap;

/// Merges vertices whose positions are identical (`tol == 0`) or within distance `tol`.
///
/// The first occurrence of a position keeps its position and its place in the vertex order;
/// later ones are replaced by it in the faces. With a tolerance, a vertex merges into the first
/// earlier *kept* vertex within `tol` (grid hashing with cells of size `tol`). Faces that become
/// degenerate (a repeated vertex) are removed; unused vertices are kept. A negative or non-finite
/// `tol` is treated as 0. `0.0` and `-0.0` are the same position; NaN coordinates never merge.
///
/// # Panics
/// If a face uses a vertex index out of range (readers and validated meshes never do).
pub fn weld(mesh: &TriMesh, tol: f64) -> TriMesh {
    let rep = if tol > 0.0 && tol.is_finite() {
        representatives_near(&mesh.positions, tol)
    } else {
        representatives_exact(&mesh.positions)
    };
    // Kept vertices are those that are their own representative; renumber in order.
    let mut new_index = vec![u32::MAX; rep.len()];
    let mut positions = Vec::new();
    for (v, &r) in rep.iter().enumerate() {
        if r as usize == v {
            new_index[v] = positions.len() as u32;
            positions.push(mesh.positions[v]);
        } else {
            new_index[v] = new_index[r as usize];
        }
    }
    let faces = mesh
        .faces
        .iter()
        .map(|f| f.map(|v| new_index[v as usize]))
        .filter(|f| f[0] != f[1] && f[1] != f[2] && f[2] != f[0])
        .collect();
    TriMesh::new(positions, faces)
}

/// For every vertex, the first vertex with exactly the same position.
fn representatives_exact(positions: &[[f64; 3]]) -> Vec<u32> {
    // -0.0 + 0.0 == 0.0, so both zeros get the same bits.
    let key = |p: &[f64; 3]| p.map(|x| (x + 0.0).to_bits());
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&v| (key(&positions[v as usize]), v));
    let mut rep: Vec<u32> = (0..positions.len() as u32).collect();
    let mut i = 0;
    while i < order.len() {
        let first = order[i];
        let p = &positions[first as usize];
        let k = key(p);
        let mut j = i + 1;
        while j < order.len() && key(&positions[order[j] as usize]) == k {
            if p.iter().all(|x| !x.is_nan()) {
                rep[order[j] as usize] = first;
            }
            j += 1;
        }
        i = j;
    }
    rep
}

/// For every vertex, the first earlier kept vertex within `tol` (itself if none).
fn representatives_near(positions: &[[f64; 3]], tol: f64) -> Vec<u32> {
    let cell = |x: f64| (x / tol).floor() as i64;
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut rep = Vec::with_capacity(positions.len());
    let tol2 = tol * tol;
    for (v, p) in positions.iter().enumerate() {
        let c = p.map(cell);
        let mut found: Option<u32> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    let Some(list) = grid.get(&key) else { continue };
                    for &w in list {
                        let q = &positions[w as usize];
                        let d2 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>();
                        if d2 <= tol2 && found.is_none_or(|f| w < f) {
                            found = Some(w);
                        }
                    }
                }
            }
        }
        match found {
            Some(w) => rep.push(w),
            None => {
                rep.push(v as u32);
                grid.entry(c).or_default().push(v as u32);
            }
        }
    }
    rep
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles of a unit square, stored STL-style (each corner separately).
    fn soup() -> TriMesh {
        TriMesh::new(
            vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [1., 1., 0.],
                [0., 0., 0.],
                [1., 1., 0.],
                [0., 1., 0.],
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
    }

    #[test]
    fn exact_weld_of_two_triangles() {
        let w = weld(&soup(), 0.0);
        assert_eq!(
            w.positions,
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]]
        );
        assert_eq!(w.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn exact_weld_ignores_near_points_and_merges_signed_zeros() {
        let mut m = soup();
        m.positions[3] = [1e-12, 0., 0.];
        m.positions[4] = [1., 1., -0.0];
        let w = weld(&m, 0.0);
        assert_eq!(w.positions.len(), 5);
        assert_eq!(w.faces, vec![[0, 1, 2], [3, 2, 4]]);
    }

    #[test]
    fn tolerance_weld_merges_near_points_into_the_first() {
        let mut m = soup();
        m.positions[3] = [1e-9, -1e-9, 0.];
        m.positions[4] = [1. - 1e-9, 1., 0.];
        let w = weld(&m, 1e-6);
        assert_eq!(w.positions[0], [0., 0., 0.]);
        assert_eq!(w.positions[2], [1., 1., 0.]);
        assert_eq!(w.positions.len(), 4);
        assert_eq!(w.faces, vec![[0, 1, 2], [0, 2, 3]]);
        // Points farther apart than the tolerance stay apart.
        assert_eq!(weld(&m, 1e-12).positions.len(), 6);
    }

    #[test]
    fn tolerance_weld_across_cell_borders() {
        // 0.0999 and 0.1001 fall in neighbouring cells (9 and 10) of size 0.01.
        let m = TriMesh::new(
            vec![[0.0999, 0., 0.], [0.1001, 0., 0.], [5., 0., 0.]],
            vec![],
        );
        let w = weld(&m, 0.01);
        assert_eq!(w.positions, vec![[0.0999, 0., 0.], [5., 0., 0.]]);
    }

    #[test]
    fn degenerate_faces_are_removed() {
        let m = TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let w = weld(&m, 0.0);
        assert_eq!(w.positions.len(), 3);
        assert_eq!(w.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn nan_never_merges_and_bad_tolerance_is_exact() {
        let m = TriMesh::new(
            vec![[f64::NAN, 0., 0.], [f64::NAN, 0., 0.], [0.; 3], [0.; 3]],
            vec![],
        );
        assert_eq!(weld(&m, 0.0).positions.len(), 3);
        assert_eq!(weld(&m, 1.0).positions.len(), 3);
        assert_eq!(weld(&m, f64::NAN).positions.len(), 3);
        assert_eq!(weld(&m, -1.0).positions.len(), 3);
    }
}
