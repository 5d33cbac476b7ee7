//! Initial maps: curvature-based boundary flattening (DEM Alg. 1), Tutte and locally authalic
//! fixed-boundary maps (Alg. 2–3), prescribed boundary shapes, and the reflection sea (Alg. 4).

pub mod boundary_flattening;
pub mod sea;
pub mod shape;
pub mod tutte;
