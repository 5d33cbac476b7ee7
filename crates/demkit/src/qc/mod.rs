//! Quasi-conformal tools: the Beltrami coefficient of a piecewise-linear map, its truncation
//! (SDEM paper (3.19)), and the linear Beltrami solver LBS (DEQ paper §3.2, (3.6)–(3.11)).

mod beltrami;
mod lbs;
mod periodic_lbs;

pub use beltrami::{
    beltrami_coefficient, beltrami_coefficient_from_frames, beltrami_coefficient_plane_to_surface,
    beltrami_coefficient_surface, beltrami_coefficient_surfaces, triangle_beltrami, truncate,
};
pub use lbs::{LinearBeltramiSolver, generalized_laplacian_weights, surface_laplacian_weights};
pub use periodic_lbs::PeriodicBeltramiSolver;
