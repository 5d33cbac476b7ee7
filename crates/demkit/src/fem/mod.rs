//! Finite-element operators on triangle meshes (DEM paper §4.3 and Appendix B):
//! cotangent Laplacian weights (4.23)/(B.6), lumped mass (4.24)/(B.8), the face gradient of a
//! piecewise-linear function (4.37), and face→vertex area-weighted averaging W^FV (4.31).

mod face_to_vertex;
mod gradient;
mod laplacian;

pub use face_to_vertex::VertexFaces;
pub use gradient::face_gradient;
pub use laplacian::{cotangent_weights, lumped_mass};
