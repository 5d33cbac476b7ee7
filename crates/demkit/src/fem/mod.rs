//! Finite-element operators on triangle meshes (DEM paper §4.3 and Appendix B):
//! cotangent Laplacian weights (4.23)/(B.6), lumped mass (4.24)/(B.8), the face gradient of a
//! piecewise-linear function (4.37), the backward-Euler diffusion step (4.34), and face→vertex averaging: area-weighted W^FV (4.31) and the plain Whitney average (4.27); and the
//! same operators on the flat torus (`UnfoldedFaces`, TDEM paper (13)–(21)).

mod diffusion;
mod dirichlet;
mod face_to_vertex;
mod gradient;
mod laplacian;
mod periodic;

pub use diffusion::{DiffusionOperator, REFACTOR_DRIFT};
pub use dirichlet::{DirichletSystem, uniform_weights};
pub use face_to_vertex::VertexFaces;
pub use gradient::{face_gradient, face_gradient_into};
pub use laplacian::{cotangent_weights, cotangent_weights_into, lumped_mass};
pub use periodic::{PeriodicSystem, UnfoldedFaces};
