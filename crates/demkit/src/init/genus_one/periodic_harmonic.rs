//! Harmonic maps of a closed genus-one mesh into the plane with prescribed periods.
//!
//! With the closed integer 1-forms `η₁, η₂` of the cut graph and lattice vectors `T₁, T₂`, the
//! translation across half-edge `i→j` is `τ(i→j) = η₁(i→j) T₁ + η₂(i→j) T₂`, and the image of
//! the half-edge is `X_j − X_i + τ(i→j)`. The harmonic map minimises
//! `Σ_edges w_ij |X_j − X_i + τ(i→j)|²` with one vertex pinned: `L X = b`,
//! `b_i = Σ_j w_ij τ(i→j)`, the same symmetric positive definite matrix for both coordinates.
//!
//! The solution is linear in the periods: `X = U₁ T₁ + U₂ T₂`, where `U_k` is the scalar
//! harmonic function with the single period 1 along `η_k` (`L U_k = Σ_j w_ij η_k(i→j)`).
//! Solving for `(U₁, U₂)` once — the map onto the unit lattice `Z²` — gives the harmonic map
//! for every lattice as a linear image of it.

use crate::Result;
use crate::fem::PeriodicSystem;

/// The harmonic map onto the unit-lattice torus `R² / Z²`: vertex `v` at `(u[0][v], u[1][v])`,
/// corner `k` of face `f` at that point plus [`corner_offset`]`(forms, f, k)`.
#[derive(Debug, Clone)]
pub struct UnitMap {
    /// The two coordinates, one value per vertex.
    pub u: [Vec<f64>; 2],
}

impl UnitMap {
    /// Corner `k` of face `f` in the unfolded plane.
    pub fn corner(&self, faces: &[[u32; 3]], forms: [&[i64]; 2], f: usize, k: usize) -> [f64; 2] {
        let v = faces[f][k] as usize;
        let o = corner_offset(forms, f, k);
        [self.u[0][v] + o[0] as f64, self.u[1][v] + o[1] as f64]
    }

    /// The three unfolded corners of face `f`.
    pub fn face(&self, faces: &[[u32; 3]], forms: [&[i64]; 2], f: usize) -> [[f64; 2]; 3] {
        std::array::from_fn(|k| self.corner(faces, forms, f, k))
    }
}

/// The lattice translation of corner `k` of face `f` relative to corner 0, in units of the
/// lattice vectors: the sum of the forms along the face's half-edges from corner 0 to `k`.
pub fn corner_offset(forms: [&[i64]; 2], f: usize, k: usize) -> [i64; 2] {
    let sum = |form: &[i64]| form[3 * f..3 * f + k].iter().sum();
    [sum(forms[0]), sum(forms[1])]
}

/// The periodic Laplace system of one mesh ([`PeriodicSystem`]) with the pinned vertices held
/// at 0, reused for every choice of weights.
#[derive(Debug)]
pub struct PeriodicLaplacian {
    system: PeriodicSystem,
    n_vertices: usize,
}

impl PeriodicLaplacian {
    /// Analyses the system of `faces` on `n_vertices` vertices with the vertices `pinned` held
    /// at 0 (one vertex of the surface, plus any vertex no face uses).
    ///
    /// Errors: [`crate::Error::Numerical`] when the symbolic analysis fails.
    pub fn new(n_vertices: usize, faces: &[[u32; 3]], pinned: &[bool]) -> Result<Self> {
        Ok(Self {
            system: PeriodicSystem::new(n_vertices, faces, pinned)?,
            n_vertices,
        })
    }

    /// Solves the two unit-period harmonic problems `L U_k = Σ_j w_ij η_k(i→j)` for the
    /// per-corner edge weights `weights` (entry `c` of face `f` weighs the edge opposite corner
    /// `c`, as in [`crate::fem::cotangent_weights`]) and the closed forms `forms` (one value
    /// per half-edge `3f + c`, from corner `c` to corner `c + 1`): the corners are translated
    /// by [`corner_offset`].
    ///
    /// Errors: [`crate::Error::Numerical`] when the matrix is not positive definite (weights of the
    /// wrong sign or not finite) or the solution is not finite.
    pub fn solve(
        &self,
        faces: &[[u32; 3]],
        weights: &[[f64; 3]],
        forms: [&[i64]; 2],
    ) -> Result<UnitMap> {
        let shift = |f: usize, k: usize| corner_offset(forms, f, k).map(|o| o as f64);
        let x = self
            .system
            .solve(faces, weights, shift, &vec![[0.0; 2]; self.n_vertices])?;
        Ok(UnitMap {
            u: std::array::from_fn(|k| x.iter().map(|p| p[k]).collect()),
        })
    }
}

/// The Gram matrix `G_kl = Σ_f Σ_c w_fc d_k d_l` of the two coordinates of `map` under the
/// per-corner edge weights `weights`, where `d` is the unfolded image of the edge opposite
/// corner `c` of face `f`. With cotangent weights this is the Dirichlet energy
/// form: the map `X = A (U₁, U₂)` has energy `tr(A G Aᵀ)` for any 2×2 matrix `A`.
pub fn dirichlet_gram(
    faces: &[[u32; 3]],
    weights: &[[f64; 3]],
    forms: [&[i64]; 2],
    map: &UnitMap,
) -> [[f64; 2]; 2] {
    let mut g = [[0.0; 2]; 2];
    for (f, wf) in weights.iter().enumerate().take(faces.len()) {
        let p = map.face(faces, forms, f);
        for (c, &w) in wf.iter().enumerate() {
            let (a, b) = (p[(c + 1) % 3], p[(c + 2) % 3]);
            let d = [b[0] - a[0], b[1] - a[1]];
            g[0][0] += w * d[0] * d[0];
            g[0][1] += w * d[0] * d[1];
            g[1][1] += w * d[1] * d[1];
        }
    }
    g[1][0] = g[0][1];
    g
}

/// The sum of the signed areas of the unfolded faces of `map`: ±1 (the unit lattice's
/// covolume times the map's degree) for any map with these periods, folded or not.
pub fn total_signed_area(faces: &[[u32; 3]], forms: [&[i64]; 2], map: &UnitMap) -> f64 {
    (0..faces.len())
        .map(|f| {
            let [a, b, c] = map.face(faces, forms, f);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .sum()
}
