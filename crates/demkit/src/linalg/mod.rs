//! Sparse linear algebra: assembly of mesh stiffness matrices over a fixed sparsity pattern,
//! a Cholesky factorization whose symbolic analysis is done once per pattern, and a sparse LU
//! for the few non-symmetric systems.
//!
//! Every FEM-type matrix demkit solves with (cotangent Laplacian plus mass, the locally authalic
//! matrix, the generalized Laplacian of the linear Beltrami solver) has the form
//! `M_ij = -Σ w_T(ij)` over the faces `T` containing edge `ij` and `M_ii = Σ_j w(ij) + d_i`,
//! where each face contributes one weight per edge. [`StiffnessPattern`] stores that structure
//! once; only the per-face edge weights change from one iteration to the next.

mod cholesky;
mod dense;
mod element;
mod lu;
mod order;
mod pattern;

pub use cholesky::{SparseCholesky, minimum_degree_order};
pub use dense::solve_dense;
pub use element::{ElementPattern, packed_index};
pub use lu::solve_lu;
pub use order::VertexOrder;
pub use pattern::StiffnessPattern;
