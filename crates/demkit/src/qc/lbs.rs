//! The linear Beltrami solver (LBS), DEQ paper §3.2: reconstruct a map f = u + iv from its
//! Beltrami coefficient by solving ∇·(A ∇u) = 0 and ∇·(A ∇v) = 0 (3.11) with the same
//! symmetric positive definite coefficient matrix A(μ) of (3.8), discretised with linear
//! finite elements (the "generalized Laplacian") and Dirichlet boundary values.

use crate::Result;
use crate::fem::DirichletSystem;
use crate::geometry::local_frame;
use num_complex::Complex64;
use rayon::prelude::*;

/// Per-face edge weights of the generalized Laplacian of (3.11) on the planar source mesh
/// (x, y; counter-clockwise faces): entry `c` is `−Area(T) ∇φ_a · A_T ∇φ_b` for the other two
/// corners `a, b`. With μ = 0 (A = I) these are the cotangent weights `½ cot θ_c`.
/// Requires |μ| < 1 on every face (use [`super::truncate`]).
pub fn generalized_laplacian_weights(
    source: &[[f64; 3]],
    faces: &[[u32; 3]],
    mu: &[Complex64],
) -> Vec<[f64; 3]> {
    per_face_weights(faces, mu, |f| {
        f.map(|v| [source[v as usize][0], source[v as usize][1]])
    })
}

/// [`generalized_laplacian_weights`] for a source surface in R³: every triangle in its own
/// orthonormal frame ([`local_frame`]), in which `mu` is expressed as well (as
/// [`super::beltrami_coefficient_surface`] gives it). The weights do not depend on the frame,
/// so LBS reconstructs the map from the surface directly.
pub fn surface_laplacian_weights(
    surface: &[[f64; 3]],
    faces: &[[u32; 3]],
    mu: &[Complex64],
) -> Vec<[f64; 3]> {
    per_face_weights(faces, mu, |f| local_frame(f.map(|v| surface[v as usize])))
}

/// [`triangle_weights`] of every face, its corners in the plane given by `corners`.
fn per_face_weights(
    faces: &[[u32; 3]],
    mu: &[Complex64],
    corners: impl Fn(&[u32; 3]) -> [[f64; 2]; 3] + Sync,
) -> Vec<[f64; 3]> {
    faces
        .par_iter()
        .zip(mu.par_iter())
        .map(|(f, m)| triangle_weights(corners(f), *m))
        .collect()
}

/// The generalized Laplacian weights of one counter-clockwise source triangle `p` for the
/// Beltrami coefficient `m` (|m| < 1): entry `c` is `−Area ∇φ_a · A ∇φ_b` for the other two
/// corners `a, b`, with A of (3.8). Zero for a degenerate or clockwise triangle.
fn triangle_weights(p: [[f64; 2]; 3], m: Complex64) -> [f64; 3] {
    let twice_area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    if twice_area <= 0.0 {
        return [0.0; 3];
    }
    // (3.8), with μ = ρ + iτ.
    let (rho, tau) = (m.re, m.im);
    let den = 1.0 - rho * rho - tau * tau;
    let a1 = ((rho - 1.0).powi(2) + tau * tau) / den;
    let a2 = -2.0 * tau / den;
    let a3 = (1.0 + 2.0 * rho + rho * rho + tau * tau) / den;
    // ∇φ_k · 2A = rot90(p_{k+2} − p_{k+1}) with rot90(x, y) = (−y, x).
    let g: [[f64; 2]; 3] = std::array::from_fn(|k| {
        let (b, c) = (p[(k + 1) % 3], p[(k + 2) % 3]);
        [-(c[1] - b[1]), c[0] - b[0]]
    });
    let form =
        |x: [f64; 2], y: [f64; 2]| x[0] * (a1 * y[0] + a2 * y[1]) + x[1] * (a2 * y[0] + a3 * y[1]);
    // Area ∇φ_a·A∇φ_b = form(g_a, g_b) / (4 Area) = form / (2 · twice_area).
    std::array::from_fn(|c| -form(g[(c + 1) % 3], g[(c + 2) % 3]) / (2.0 * twice_area))
}

/// LBS with a fixed set of Dirichlet vertices on a fixed connectivity: the sparsity pattern and
/// its symbolic Cholesky analysis are computed once, each [`solve`](Self::solve) refactors
/// numerically.
#[derive(Debug)]
pub struct LinearBeltramiSolver {
    faces: Vec<[u32; 3]>,
    system: DirichletSystem,
}

impl LinearBeltramiSolver {
    /// Prepares the solver for meshes with this connectivity and these fixed vertices
    /// (at least one vertex must be fixed, two for a unique planar map).
    pub fn new(n_vertices: usize, faces: &[[u32; 3]], fixed: &[bool]) -> Result<Self> {
        Self::in_order(n_vertices, faces, fixed, None)
    }

    /// As [`new`](Self::new), eliminating the free vertices in the connectivity's `order`
    /// when one is given ([`crate::linalg::VertexOrder`]).
    pub fn in_order(
        n_vertices: usize,
        faces: &[[u32; 3]],
        fixed: &[bool],
        order: Option<&crate::linalg::VertexOrder>,
    ) -> Result<Self> {
        Ok(Self {
            faces: faces.to_vec(),
            system: DirichletSystem::in_order(n_vertices, faces, fixed, order)?,
        })
    }

    /// Reconstructs the map with Beltrami coefficient `mu` (per face, |μ| < 1) on the planar
    /// `source` mesh, with fixed vertices sent to `boundary[v]` (other entries are ignored).
    /// Returns the planar image of every vertex (z = 0).
    pub fn solve(
        &self,
        source: &[[f64; 3]],
        mu: &[Complex64],
        boundary: &[[f64; 3]],
    ) -> Result<Vec<[f64; 3]>> {
        let w = generalized_laplacian_weights(source, &self.faces, mu);
        self.system.solve(&w, boundary)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::cotangent_weights;
    use crate::generate_fixtures::grid;
    use crate::qc::beltrami_coefficient;

    #[test]
    fn zero_mu_gives_cotangent_weights() {
        let (pos, faces, _) = grid(3, 0.2);
        let mu = vec![Complex64::new(0.0, 0.0); faces.len()];
        let w = generalized_laplacian_weights(&pos, &faces, &mu);
        let c = cotangent_weights(&pos, &faces);
        for (a, b) in w.iter().zip(&c) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn reproduces_affine_quasiconformal_map() {
        // f(z) = z + k z̄ + t has constant μ = k; with its boundary values, LBS(μ) = f exactly.
        let (pos, faces, boundary) = grid(8, 0.2);
        let k = Complex64::new(0.35, -0.2);
        let f = |p: [f64; 3]| {
            let z = Complex64::new(p[0], p[1]);
            let w = z + k * z.conj() + Complex64::new(0.5, -1.0);
            [w.re, w.im, 0.0]
        };
        let target: Vec<[f64; 3]> = pos.iter().map(|&p| f(p)).collect();
        let mu = vec![k; faces.len()];
        let lbs = LinearBeltramiSolver::new(pos.len(), &faces, &boundary).unwrap();
        let out = lbs.solve(&pos, &mu, &target).unwrap();
        for (a, b) in out.iter().zip(&target) {
            assert!((a[0] - b[0]).abs() < 1e-10 && (a[1] - b[1]).abs() < 1e-10);
        }
    }

    #[test]
    fn zero_mu_reproduces_conformal_map_and_recovers_mu() {
        // Boundary values of a Möbius-like conformal map; LBS(0) is close to it and its μ is small.
        let (pos, faces, boundary) = grid(16, 0.1);
        let f = |p: [f64; 3]| {
            let z = Complex64::new(p[0], p[1]);
            let w = (z + 0.3) / (Complex64::new(0.1, 0.2) * z + 2.0);
            [w.re, w.im, 0.0]
        };
        let target: Vec<[f64; 3]> = pos.iter().map(|&p| f(p)).collect();
        let lbs = LinearBeltramiSolver::new(pos.len(), &faces, &boundary).unwrap();
        let out = lbs
            .solve(&pos, &vec![Complex64::new(0.0, 0.0); faces.len()], &target)
            .unwrap();
        let err = out
            .iter()
            .zip(&target)
            .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
            .fold(0.0, f64::max);
        assert!(err < 1e-3, "max error {err}");
        let mu = beltrami_coefficient(&pos, &out, &faces);
        let mean: f64 = mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64;
        assert!(mean < 0.02, "mean |mu| {mean}");
    }
}
