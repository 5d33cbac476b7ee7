//! Face→vertex area-weighted averaging W^FV (4.29)–(4.31).

use rayon::prelude::*;

/// Vertex–face incidence (CSR) used to apply W^FV: for each vertex, the faces that count
/// towards its average. Built once per connectivity.
#[derive(Debug, Clone)]
pub struct VertexFaces {
    ptr: Vec<usize>,
    faces: Vec<u32>,
}

impl VertexFaces {
    /// Incidence of every face with its three vertices.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Self {
        Self::new_filtered(n_vertices, faces, |_, _| true)
    }

    /// Incidence keeping only the pairs (vertex, face) for which `keep` is true — e.g. to
    /// average only over the region of interest at its boundary (DEM paper, after (4.32)).
    pub fn new_filtered(
        n_vertices: usize,
        faces: &[[u32; 3]],
        keep: impl Fn(usize, usize) -> bool,
    ) -> Self {
        let (ptr, faces) = crate::mesh::topology::vertex_faces_where(n_vertices, faces, keep);
        Self { ptr, faces }
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.ptr.len() - 1
    }

    /// The faces counted for vertex `v`.
    pub fn faces_of(&self, v: usize) -> &[u32] {
        &self.faces[self.ptr[v]..self.ptr[v + 1]]
    }

    /// W^FV applied to a face function (4.29): `ρ_V(v) = Σ_T Area(T) ρ_F(T) / Σ_T Area(T)` over
    /// the faces of `v`. Vertices without faces get 0.
    pub fn apply(&self, face_areas: &[f64], face_values: &[f64]) -> Vec<f64> {
        (0..self.n_vertices())
            .into_par_iter()
            .map(|v| {
                let (mut s, mut w) = (0.0, 0.0);
                for &f in self.faces_of(v) {
                    let a = face_areas[f as usize];
                    s += a * face_values[f as usize];
                    w += a;
                }
                if w > 0.0 { s / w } else { 0.0 }
            })
            .collect()
    }

    /// The sum of a face function over each vertex's faces: `s(v) = Σ_T f(T)`.
    pub fn sum(&self, face_values: &[f64]) -> Vec<f64> {
        (0..self.n_vertices())
            .into_par_iter()
            .map(|v| {
                self.faces_of(v)
                    .iter()
                    .map(|&f| face_values[f as usize])
                    .sum()
            })
            .collect()
    }

    /// The plain average of a face function over each vertex's faces, the Whitney
    /// interpolation (4.27): `f(v) = Σ_T f(T) / |N(v)|`. Vertices without faces get 0.
    pub fn average(&self, face_values: &[f64]) -> Vec<f64> {
        (0..self.n_vertices())
            .into_par_iter()
            .map(|v| {
                let fs = self.faces_of(v);
                if fs.is_empty() {
                    return 0.0;
                }
                fs.iter().map(|&f| face_values[f as usize]).sum::<f64>() / fs.len() as f64
            })
            .collect()
    }

    /// W^FV applied to a face vector field (each component averaged as in [`apply`](Self::apply)).
    pub fn apply_vec(&self, face_areas: &[f64], face_values: &[[f64; 3]]) -> Vec<[f64; 3]> {
        (0..self.n_vertices())
            .into_par_iter()
            .map(|v| {
                let mut s = [0.0; 3];
                let mut w = 0.0;
                for &f in self.faces_of(v) {
                    let a = face_areas[f as usize];
                    let x = face_values[f as usize];
                    s = [s[0] + a * x[0], s[1] + a * x[1], s[2] + a * x[2]];
                    w += a;
                }
                if w > 0.0 {
                    [s[0] / w, s[1] / w, s[2] / w]
                } else {
                    [0.0; 3]
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_average_ignores_areas() {
        let faces = [[0u32, 1, 2], [0, 2, 3]];
        let w = VertexFaces::new(4, &faces);
        let r = w.average(&[2.0, 6.0]);
        assert_eq!(r, vec![4.0, 2.0, 4.0, 6.0]);
    }

    #[test]
    fn sums_over_the_faces_of_each_vertex() {
        let faces = [[0u32, 1, 2], [0, 2, 3]];
        let w = VertexFaces::new(5, &faces);
        assert_eq!(w.sum(&[2.0, 6.0]), vec![8.0, 2.0, 8.0, 6.0, 0.0]);
        // The area-weighted average of P/A is the ratio of the sums of P and of A.
        let (a, p) = ([1.5, 0.5], [3.0, 4.0]);
        let ratio: Vec<f64> = w
            .sum(&p)
            .iter()
            .zip(w.sum(&a))
            .map(|(p, a)| p / a)
            .collect();
        let avg = w.apply(&a, &[p[0] / a[0], p[1] / a[1]]);
        for v in 0..4 {
            assert!((ratio[v] - avg[v]).abs() < 1e-15, "{ratio:?} {avg:?}");
        }
    }

    #[test]
    fn area_weighted_average() {
        // Two faces sharing vertices 0 and 2.
        let faces = [[0u32, 1, 2], [0, 2, 3]];
        let w = VertexFaces::new(4, &faces);
        let r = w.apply(&[1.0, 3.0], &[2.0, 6.0]);
        assert_eq!(r[1], 2.0);
        assert_eq!(r[3], 6.0);
        assert_eq!(r[0], (1.0 * 2.0 + 3.0 * 6.0) / 4.0);
        // Rows of W^FV sum to one: a constant is reproduced.
        assert!(
            w.apply(&[0.7, 0.1], &[5.0, 5.0])
                .iter()
                .all(|&x| (x - 5.0).abs() < 1e-15)
        );
    }

    #[test]
    fn filtered_incidence_ignores_other_faces() {
        let faces = [[0u32, 1, 2], [0, 2, 3]];
        let w = VertexFaces::new_filtered(4, &faces, |_, f| f == 0);
        let r = w.apply(&[1.0, 3.0], &[2.0, 6.0]);
        assert_eq!(r[0], 2.0);
        assert_eq!(r[3], 0.0);
    }
}
