//! The backward-Euler diffusion step of the density (DEM paper (4.33)–(4.34), SDEM paper (3.9))
//! on a fixed connectivity: `(A + t L) ρ = A ρ₀`, with `A` the lumped mass and `L` the cotangent
//! Laplacian of the current positions. The sparsity pattern and its symbolic Cholesky analysis
//! are computed once; every [`factor`](DiffusionOperator::factor) only assembles and refactors
//! numerically, reusing its buffers. [`factor_lazily`](DiffusionOperator::factor_lazily) skips
//! even that while the map has barely changed since the last factorization.

use super::{cotangent_weights_into, lumped_mass};
use crate::linalg::{SparseCholesky, StiffnessPattern, VertexOrder};
use crate::metrics::log_area_misfit;
use crate::{Error, Result};
use std::cell::{Cell, Ref, RefCell, RefMut};

/// How far a map's face areas may drift from those of the map last factored before
/// [`DiffusionOperator::factor_lazily`] factors again: the mean |ln| of the ratio of the
/// normalised areas ([`log_area_misfit`]). Near the end of a run the map changes by a fraction
/// of a percent per iteration, and a factorization costs several times the rest of an
/// iteration (measurements in `docs/deviations.md`).
pub const REFACTOR_DRIFT: f64 = 0.02;

/// `A + t L` on one connectivity, ready to be refactored for new positions.
pub struct DiffusionOperator {
    faces: Vec<[u32; 3]>,
    pattern: StiffnessPattern,
    cholesky: RefCell<SparseCholesky>,
    weights: RefCell<Vec<[f64; 3]>>,
    values: RefCell<Vec<f64>>,
    /// The lumped mass of the map the solver was last factored for.
    mass: RefCell<Vec<f64>>,
    /// The map the solver holds, when it was factored by
    /// [`factor_lazily`](DiffusionOperator::factor_lazily).
    last: RefCell<Option<Factored>>,
    /// How many numeric factorizations were made.
    factorizations: Cell<usize>,
}

/// The map a lazily made factorization was built from: its diffusion time and face areas.
struct Factored {
    t: f64,
    areas: Vec<f64>,
}

impl std::fmt::Debug for DiffusionOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiffusionOperator")
            .field("faces", &self.faces.len())
            .field("cholesky", &self.cholesky)
            .finish()
    }
}

/// A factorization of `A + t L` with the lumped mass `A` it was built from. It holds its
/// operator's solver: the operator cannot be refactored while a factor is alive.
pub struct DiffusionFactor<'a> {
    /// The operator's solver, factored for `A + t L` (plus any extra diagonal).
    solver: RefMut<'a, SparseCholesky>,
    /// The lumped mass `A` (4.24) of the map the factorization was made from.
    pub mass: Ref<'a, Vec<f64>>,
}

impl DiffusionFactor<'_> {
    /// One diffusion step of the vertex function `rho` (4.34): solves `(A + t L) ρ = A ρ₀` and
    /// floors the result at a thousandth of the smallest value of `rho` (the step is positive
    /// in exact arithmetic; the floor keeps `∇ρ / ρ` finite after rounding).
    pub fn diffuse(&mut self, rho: &[f64]) -> Result<Vec<f64>> {
        let mut out: Vec<f64> = self.mass.iter().zip(rho).map(|(a, p)| a * p).collect();
        self.solver.solve_in_place(&mut out)?;
        let floor = rho.iter().cloned().fold(f64::INFINITY, f64::min) * 1e-3;
        for x in out.iter_mut() {
            if !(*x > floor) {
                *x = floor;
            }
        }
        Ok(out)
    }

    /// Solves `(A + t L) X = B` in place for `k` right-hand sides stored column-major in `b`
    /// ([`SparseCholesky::solve_many_in_place`]).
    pub fn solve_many_in_place(&mut self, b: &mut [f64], k: usize) -> Result<()> {
        self.solver.solve_many_in_place(b, k)
    }
}

impl DiffusionOperator {
    /// Analyses the sparsity pattern of `faces` on `n_vertices` vertices (no fixed vertices).
    pub fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Self> {
        Self::in_order(n_vertices, faces, None)
    }

    /// As [`new`](Self::new), eliminating the vertices in the connectivity's `order` when one
    /// is given ([`VertexOrder`]).
    pub fn in_order(
        n_vertices: usize,
        faces: &[[u32; 3]],
        order: Option<&VertexOrder>,
    ) -> Result<Self> {
        let pattern = StiffnessPattern::new(n_vertices, faces, None);
        let cholesky = RefCell::new(SparseCholesky::for_stiffness_in(&pattern, order)?);
        let values = RefCell::new(vec![0.0; pattern.nnz()]);
        Ok(Self {
            faces: faces.to_vec(),
            pattern,
            cholesky,
            weights: RefCell::new(Vec::new()),
            values,
            mass: RefCell::new(Vec::new()),
            last: RefCell::new(None),
            factorizations: Cell::new(0),
        })
    }

    /// [`factor`](Self::factor) without the extra diagonal, unless the solver already holds a
    /// factorization made here for a time within a factor e^`drift` of `t`, from a map whose
    /// face areas differ from `areas`
    /// by at most `drift` (their face misfit [`log_area_misfit`], the mean |ln| of the
    /// ratio of the normalised areas). Then that factorization is returned, with the mass
    /// of the map it was made from: `(A₀ + t L₀) ρ = A₀ ρ₀` still leaves a constant ρ₀ as it
    /// is and conserves ∫ρ, and differs from the current operator by about `drift`.
    pub fn factor_lazily(
        &self,
        positions: &[[f64; 3]],
        areas: &[f64],
        t: f64,
        drift: f64,
    ) -> Result<DiffusionFactor<'_>> {
        let held = self.last.borrow().as_ref().is_some_and(|f| {
            (t / f.t).ln().abs() <= drift && log_area_misfit(&f.areas, areas) <= drift
        });
        if held {
            return Ok(DiffusionFactor {
                solver: self.solver()?,
                mass: self.mass.borrow(),
            });
        }
        let factor = self.factor(positions, areas, t, &[])?;
        *self.last.borrow_mut() = Some(Factored {
            t,
            areas: areas.to_vec(),
        });
        Ok(factor)
    }

    /// How many numeric factorizations this operator has made.
    pub fn factorizations(&self) -> usize {
        self.factorizations.get()
    }

    /// Factors `A + t L + D` for the mesh at `positions` with face areas `areas`, where `D` is
    /// the diagonal `extra_diagonal` (vertex, value) pairs add (e.g. LSDEM's landmark penalty).
    pub fn factor(
        &self,
        positions: &[[f64; 3]],
        areas: &[f64],
        t: f64,
        extra_diagonal: &[(usize, f64)],
    ) -> Result<DiffusionFactor<'_>> {
        let mut weights = self.weights.borrow_mut();
        cotangent_weights_into(positions, &self.faces, &mut weights);
        for w in weights.iter_mut() {
            *w = w.map(|c| c * t);
        }
        let mass = lumped_mass(positions.len(), &self.faces, areas);
        self.assemble_and_factor(&weights, mass, extra_diagonal)
    }

    /// Factors `A + t L + D` from the cotangent weights of every face (per corner, as
    /// [`cotangent_weights`](super::cotangent_weights) gives them) and the lumped mass `A`:
    /// for meshes whose faces are not drawn from one position per vertex (the flat torus).
    pub fn factor_weights(
        &self,
        weights: &[[f64; 3]],
        mass: Vec<f64>,
        t: f64,
        extra_diagonal: &[(usize, f64)],
    ) -> Result<DiffusionFactor<'_>> {
        let mut scaled = self.weights.borrow_mut();
        scaled.clear();
        scaled.extend(weights.iter().map(|w| w.map(|c| c * t)));
        self.assemble_and_factor(&scaled, mass, extra_diagonal)
    }

    /// Assembles `A + L_w + D` from already scaled weights and factors it.
    fn assemble_and_factor(
        &self,
        scaled_weights: &[[f64; 3]],
        mass: Vec<f64>,
        extra_diagonal: &[(usize, f64)],
    ) -> Result<DiffusionFactor<'_>> {
        let mut diagonal = mass.clone();
        for &(v, d) in extra_diagonal {
            diagonal[v] += d;
        }
        let mut values = self.values.borrow_mut();
        self.pattern
            .assemble(scaled_weights, &diagonal, &mut values);
        let mut solver = self.solver()?;
        *self.last.borrow_mut() = None;
        *self.mass.borrow_mut() = mass;
        self.factorizations.set(self.factorizations.get() + 1);
        solver.factor(&values)?;
        Ok(DiffusionFactor {
            solver,
            mass: self.mass.borrow(),
        })
    }

    /// The solver, unless a factor still holds it.
    fn solver(&self) -> Result<RefMut<'_, SparseCholesky>> {
        self.cholesky.try_borrow_mut().map_err(|_| {
            Error::Numerical("diffusion operator refactored while its factor is in use".into())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;
    use crate::geometry::face_areas;

    #[test]
    fn constants_are_steady_and_mass_is_conserved() {
        let (pos, faces, _) = grid(6, 0.2);
        let op = DiffusionOperator::new(pos.len(), &faces).unwrap();
        let areas = face_areas(&pos, &faces);
        let mut f = op.factor(&pos, &areas, 0.05, &[]).unwrap();
        // L 1 = 0: a constant does not diffuse.
        for x in f.diffuse(&vec![2.5; pos.len()]).unwrap() {
            assert!((x - 2.5).abs() < 1e-12);
        }
        // 1ᵀ (A + tL) ρ = 1ᵀ A ρ: the total ∫ρ is conserved, and a peak spreads out.
        let mut peak = vec![1.0; pos.len()];
        peak[20] = 10.0;
        let out = f.diffuse(&peak).unwrap();
        let total = |r: &[f64]| r.iter().zip(f.mass.iter()).map(|(a, b)| a * b).sum::<f64>();
        assert!((total(&out) - total(&peak)).abs() < 1e-12);
        assert!(out[20] < 10.0 && out[20] > 1.0);
    }

    #[test]
    fn a_lazy_factor_is_reused_only_while_the_areas_barely_change() {
        let (pos, faces, boundary) = grid(6, 0.2);
        let op = DiffusionOperator::new(pos.len(), &faces).unwrap();
        let areas = face_areas(&pos, &faces);
        let mut peak = vec![1.0; pos.len()];
        peak[20] = 10.0;
        let fresh = op
            .factor_lazily(&pos, &areas, 0.05, 0.02)
            .unwrap()
            .diffuse(&peak);
        assert_eq!(op.factorizations(), 1);

        // Interior vertices moved so that the face areas change by about 1 %, then 5 %.
        let nudged = |eps: f64| -> Vec<[f64; 3]> {
            pos.iter()
                .zip(&boundary)
                .map(|(p, &b)| {
                    let s = if b {
                        0.0
                    } else {
                        eps * (7.0 * p[0] + 3.0 * p[1]).sin()
                    };
                    [p[0] + 0.1 * s, p[1] - 0.1 * s, 0.0]
                })
                .collect()
        };
        let small = nudged(0.02);
        let small_areas = face_areas(&small, &faces);
        let drift = log_area_misfit(&areas, &small_areas);
        assert!(drift > 0.0 && drift < 0.02, "{drift}");
        // Reused, with the mass it was made from: the same result as before, constants steady.
        let mut f = op.factor_lazily(&small, &small_areas, 0.05, 0.02).unwrap();
        assert_eq!(f.diffuse(&peak).unwrap(), fresh.unwrap());
        for x in f.diffuse(&vec![2.5; pos.len()]).unwrap() {
            assert!((x - 2.5).abs() < 1e-12);
        }
        drop(f);
        assert_eq!(op.factorizations(), 1);
        // Another diffusion time, or areas that drifted further, are factored anew.
        drop(op.factor_lazily(&small, &small_areas, 0.1, 0.02).unwrap());
        assert_eq!(op.factorizations(), 2);
        let large = nudged(0.3);
        let large_areas = face_areas(&large, &faces);
        assert!(log_area_misfit(&small_areas, &large_areas) > 0.02);
        drop(op.factor_lazily(&large, &large_areas, 0.1, 0.02).unwrap());
        assert_eq!(op.factorizations(), 3);
        // A plain factorization (here with an extra diagonal) replaces what was held.
        drop(op.factor(&large, &large_areas, 0.1, &[(3, 1.0)]).unwrap());
        drop(op.factor_lazily(&large, &large_areas, 0.1, 0.02).unwrap());
        assert_eq!(op.factorizations(), 5);
    }

    #[test]
    fn extra_diagonal_enters_the_matrix() {
        let (pos, faces, _) = grid(4, 0.2);
        let op = DiffusionOperator::new(pos.len(), &faces).unwrap();
        let areas = face_areas(&pos, &faces);
        // With t = 0 the system is diag(A + D): solving A x = (A + D) 1 gives x = 1 except at v.
        let mut f = op.factor(&pos, &areas, 0.0, &[(3, 1.0)]).unwrap();
        let mut b = f.mass.clone();
        f.solve_many_in_place(&mut b, 1).unwrap();
        // The operator is not refactored while its factor is alive.
        assert!(op.factor(&pos, &areas, 0.0, &[]).is_err());
        let expect = f.mass[3] / (f.mass[3] + 1.0);
        assert!((b[3] - expect).abs() < 1e-12);
        assert!((b[4] - 1.0).abs() < 1e-12);
    }
}
