//! demkit — density-equalizing maps of triangulated surfaces.
//!
//! Given a triangle mesh and a positive *population* on every face, demkit deforms (or flattens)
//! the surface onto a standard domain so that population per unit area becomes uniform.
//! The maps are computed by density diffusion (Gastner–Newman), discretised with finite elements
//! on the mesh, and kept bijective with quasi-conformal (Beltrami) corrections.
//!
//! The front door: [`Surface::new`] validates a mesh, [`map`] maps it with a [`Population`]
//! and [`MapOptions`] (the method chosen by topology unless named) into a [`Map`], which says
//! where it lies ([`Domain`]) and carries the report's metrics:
//!
//! ```
//! let mesh = demkit::generate::square_grid(8, 8, 1.0, 1.0).unwrap();
//! let surface = demkit::Surface::new(mesh.positions, mesh.faces)?;
//! // An area-preserving map (population = area), the method chosen by topology (a disk: DEM).
//! let map = demkit::map(&surface, &demkit::Population::Area, &demkit::MapOptions::default())?;
//! assert_eq!(map.metrics.flipped_triangles, 0);
//! // A population given as an expression of the face centroid: twice as dense where x > 0.5.
//! let population = demkit::Population::Expression("area*(1+(x>0.5))".into());
//! let map = demkit::map(&surface, &population, &demkit::MapOptions::default())?;
//! assert!(map.metrics.face_density_var_final < map.metrics.face_density_var_initial);
//! # Ok::<(), demkit::Error>(())
//! ```
//!
//! What is API (the rest may change without notice):
//! - the front door: [`Surface`], [`map`], [`map_with_progress`], [`Map`], [`Domain`],
//!   [`MapOptions`], [`Method`], [`Population`], [`Error`];
//! - meshes and files: [`TriMesh`], [`mesh`] (topology, validation, welding), [`io`] (mesh,
//!   population and landmark files), [`population`] and [`expr`] (populations from names, files
//!   and expressions), [`generate`] (synthetic meshes);
//! - results: [`metrics`] (the report's figures, one definition each), [`report`] (the JSON
//!   report of a map, [`Map::report`]), [`shape`] (the target shapes of DEM onto a shape);
//! - applications: [`apps::remesh`], [`apps::cartogram`], [`apps::register`],
//!   [`apps::texture`];
//! - for those who compose the steps themselves: [`methods`] (each method's `Config` and `run`,
//!   by domain: `disk`, `sphere`, `circle`, `torus`, all on one iteration, `methods::common`),
//!   [`init`] (the initial maps: boundary flattening, Tutte, spherical and circle-domain
//!   conformal maps, the flat torus), [`geometry`] (areas, frames, the torus, point location).
//!
//! Internal: the finite-element operators (cotangent Laplacian, lumped mass, face gradient,
//! face→vertex averaging), the sparse solvers (assembly over a fixed pattern, one cached Cholesky,
//! LU) and the quasi-conformal tools (Beltrami coefficients, the linear Beltrami solver). The
//! benchmarks reach them through the `internals` feature, which is not a stable API.

// `!(x > 0.0)` is used on purpose: it is true for NaN, which must count as a failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod api;
pub mod apps;
pub mod error;
pub mod expr;
#[cfg(feature = "internals")]
pub mod fem;
#[cfg(not(feature = "internals"))]
pub(crate) mod fem;
pub mod generate;
#[cfg(test)]
mod generate_fixtures;
pub mod geometry;
pub mod init;
pub mod io;
#[cfg(feature = "internals")]
pub mod linalg;
#[cfg(not(feature = "internals"))]
pub(crate) mod linalg;
pub mod mesh;
pub mod methods;
pub mod metrics;
mod optimize;
pub mod options;
pub mod population;
#[cfg(feature = "internals")]
pub mod qc;
#[cfg(not(feature = "internals"))]
pub(crate) mod qc;
pub mod report;
pub mod shape;
mod surface;

pub use api::{Domain, Map, MapOptions, Method, Population, map, map_with_progress};
pub use error::{Error, Result};
pub use mesh::TriMesh;
pub use options::MapOption;
pub use shape::Shape;
pub use surface::Surface;
