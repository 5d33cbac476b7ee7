//! The fixed geometry of the conformal energy (C1)–(C2): per-face source data, and the vertex
//! farthest from the boundary.

use super::*;

/// The source surface's fixed data: each face's (C1) coefficients and the vertex–face
/// incidence.
pub(super) struct Geometry {
    pub(super) n: usize,
    pub(super) faces: Vec<[u32; 3]>,
    /// `d_k = q_{k+2} − q_{k+1}` of each face (C1).
    pub(super) face_d: Vec<[C64; 3]>,
    /// `1 / (8 A_T)` (C2).
    pub(super) face_scale: Vec<f64>,
    /// The faces around each vertex (CSR).
    pub(super) vf_ptr: Vec<usize>,
    pub(super) vf: Vec<u32>,
}

impl Geometry {
    pub(super) fn new(mesh: &TriMesh) -> Self {
        let (face_d, face_scale) = mesh
            .faces
            .par_iter()
            .map(|f| {
                let q = local_frame(f.map(|v| mesh.positions[v as usize]))
                    .map(|p| C64::new(p[0], p[1]));
                let d = std::array::from_fn(|k| q[(k + 2) % 3] - q[(k + 1) % 3]);
                let area = 0.5 * (q[1] - q[0]).re * (q[2] - q[0]).im;
                (d, if area > 0.0 { 0.125 / area } else { 0.0 })
            })
            .unzip();
        let (vf_ptr, vf) = vertex_faces(mesh.n_vertices(), &mesh.faces);
        Self {
            n: mesh.n_vertices(),
            faces: mesh.faces.clone(),
            face_d,
            face_scale,
            vf_ptr,
            vf,
        }
    }

    /// A fill-reducing elimination order of the vertices (minimum degree on the mesh graph),
    /// shared by every system: their unknowns are blocks per vertex.
    pub(super) fn vertex_order(&self) -> Result<Vec<usize>> {
        let graph = ElementPattern::new(self.n, self.faces.iter().map(|f| &f[..]))?;
        minimum_degree_order(self.n, graph.col_ptr(), graph.row_idx())
    }

    pub(super) fn faces_around(&self, v: usize) -> &[u32] {
        &self.vf[self.vf_ptr[v]..self.vf_ptr[v + 1]]
    }

    /// `Σ_k d_k w_k` of face `t` (C1, C2).
    pub(super) fn residual(&self, t: usize, z: &[C64]) -> C64 {
        let (f, d) = (self.faces[t], self.face_d[t]);
        d[0] * z[f[0] as usize] + d[1] * z[f[1] as usize] + d[2] * z[f[2] as usize]
    }

    /// The conformal energy (C2) of the planar image `z` with face weights `weights` (all 1
    /// when `None`), summed in a fixed order.
    pub(super) fn conformal_energy(&self, z: &[C64], weights: Option<&[f64]>) -> f64 {
        let per_chunk: Vec<f64> = (0..self.faces.len())
            .collect::<Vec<_>>()
            .par_chunks(4096)
            .map(|chunk| {
                chunk
                    .iter()
                    .map(|&t| {
                        let w = weights.map_or(1.0, |w| w[t]);
                        w * self.residual(t, z).norm_sqr() * self.face_scale[t]
                    })
                    .sum::<f64>()
            })
            .collect();
        per_chunk.iter().sum()
    }

    /// Gradient of (C2) per vertex, as `∂E/∂x + i ∂E/∂y`: `Σ_T 2 ω_T d̄_k r_T / (8 A_T)` over
    /// the faces `T` around the vertex, `k` its corner in `T`, `r_T = Σ_k d_k w_k`.
    pub(super) fn gradient(&self, z: &[C64], weights: &[f64]) -> Vec<C64> {
        let r: Vec<C64> = (0..self.faces.len())
            .into_par_iter()
            .map(|t| 2.0 * weights[t] * self.face_scale[t] * self.residual(t, z))
            .collect();
        (0..self.n)
            .into_par_iter()
            .map(|v| {
                self.faces_around(v)
                    .iter()
                    .map(|&t| {
                        let t = t as usize;
                        let k = self.faces[t]
                            .iter()
                            .position(|&x| x as usize == v)
                            .unwrap_or(0);
                        self.face_d[t][k].conj() * r[t]
                    })
                    .sum()
            })
            .collect()
    }
}

/// The interior vertex at the largest edge distance from every boundary loop (multi-source
/// BFS), the smallest index among ties; `None` when every vertex is on a boundary.
pub(super) fn farthest_from_boundary(geo: &Geometry, loops: &[Vec<u32>]) -> Option<u32> {
    let mut dist = vec![u32::MAX; geo.n];
    let mut queue: Vec<u32> = loops.iter().flatten().copied().collect();
    for &v in &queue {
        dist[v as usize] = 0;
    }
    let mut head = 0;
    while head < queue.len() {
        let v = queue[head] as usize;
        head += 1;
        for &t in geo.faces_around(v) {
            for &j in &geo.faces[t as usize] {
                if dist[j as usize] == u32::MAX {
                    dist[j as usize] = dist[v] + 1;
                    queue.push(j);
                }
            }
        }
    }
    let mut best: Option<(u32, u32)> = None;
    for (v, &d) in dist.iter().enumerate() {
        if d != 0 && d != u32::MAX && best.is_none_or(|(bd, _)| d > bd) {
            best = Some((d, v as u32));
        }
    }
    best.map(|(_, v)| v)
}
