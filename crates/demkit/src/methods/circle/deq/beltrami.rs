//! The Beltrami relaxation of DEQ's density-equalizing iteration (DEQ paper (5.31), (5.39)):
//! after every density move, the Beltrami coefficient ν of the map *from the surface* is
//! relaxed towards 0 along the descent of `α ∫|ν|²`, `ν ← (1 − α t) ν` over the move's time
//! `t`, and the map is rebuilt from it by the linear Beltrami solver on the surface (every
//! triangle in its own frame), the boundary loops held where they are. It keeps the iteration
//! from crushing triangles: a squeezed triangle has |ν| near 1, and the relaxation shrinks
//! 1 − |ν|'s deficit by a factor, not by an amount, which reopens it.

use crate::Result;
use crate::fem::DirichletSystem;
use crate::geometry::count_nonpositive;
use crate::qc::{beltrami_coefficient_surface, surface_laplacian_weights, truncate};
use num_complex::Complex64;

/// The weight α of the relaxation: the paper's α (§6.1).
pub(crate) const ALPHA: f64 = 0.1;

/// How many times the relaxation is halved before a move is left as it is.
const MAX_HALVINGS: usize = 4;

/// The relaxation of one surface's region.
pub(crate) struct Relaxation {
    /// The surface (the map's numbering: its vertices, then the hole fillings' points).
    surface: Vec<[f64; 3]>,
    faces: Vec<[u32; 3]>,
    /// The linear Beltrami solver's system, every vertex in `held` fixed.
    system: DirichletSystem,
}

impl Relaxation {
    /// The relaxation of the region `faces` of `surface` with the vertices where `held` is
    /// true fixed.
    pub fn new(surface: &[[f64; 3]], faces: &[[u32; 3]], held: &[bool]) -> Result<Self> {
        Ok(Self {
            surface: surface.to_vec(),
            faces: faces.to_vec(),
            system: DirichletSystem::new(held.len(), faces, held)?,
        })
    }

    /// Relaxes the map `x` in place after a move over time `time` (at most halving ν); leaves
    /// it unchanged when every attempt would fold a triangle.
    pub fn apply(&self, x: &mut [[f64; 3]], time: f64) {
        let mut s = (ALPHA * time).min(0.5);
        if !(s > 0.0) {
            return;
        }
        let mu = beltrami_coefficient_surface(&self.surface, x, &self.faces);
        for _ in 0..MAX_HALVINGS {
            let nu: Vec<Complex64> = mu
                .iter()
                .map(|&m| {
                    if m.norm() < 1.0 {
                        m * (1.0 - s)
                    } else {
                        // A collapsed triangle: the truncation of (5.43).
                        truncate(m, 0.1)
                    }
                })
                .collect();
            let w = surface_laplacian_weights(&self.surface, &self.faces, &nu);
            if let Ok(y) = self.system.solve(&w, x)
                && count_nonpositive(&y, &self.faces) == 0
            {
                x.copy_from_slice(&y);
                return;
            }
            s *= 0.5;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;

    #[test]
    fn a_sheared_grid_relaxes_towards_conformal() {
        // The planar grid sheared by x ↦ x + 0.5 y inside, its boundary held: the relaxation
        // lowers the mean |μ| of the map from the unsheared grid and keeps the boundary.
        let (pos, faces, boundary) = grid(8, 0.0);
        let sheared: Vec<[f64; 3]> = pos
            .iter()
            .zip(&boundary)
            .map(|(p, &b)| {
                let bump = if b { 0.0 } else { 0.3 * p[1] * (1.0 - p[1]) };
                [p[0] + bump, p[1], 0.0]
            })
            .collect();
        let mean_mu = |x: &[[f64; 3]]| {
            let mu = beltrami_coefficient_surface(&pos, x, &faces);
            mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64
        };
        let relax = Relaxation::new(&pos, &faces, &boundary).unwrap();
        let mut x = sheared.clone();
        relax.apply(&mut x, 1.0);
        assert!(mean_mu(&x) < 0.95 * mean_mu(&sheared));
        assert_eq!(count_nonpositive(&x, &faces), 0);
        for (v, &b) in boundary.iter().enumerate() {
            if b {
                assert_eq!(x[v], sheared[v]);
            }
        }
    }
}
