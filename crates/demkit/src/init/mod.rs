//! Initial maps: curvature-based boundary flattening (DEM Alg. 1), Tutte and locally authalic
//! fixed-boundary maps (Alg. 2–3), the reflection sea (Alg. 4), and
//! the spherical conformal map of a genus-0 closed surface with its Möbius area correction, and
//! the conformal map of a multiply connected open surface onto a circle domain with the disk
//! automorphism that balances its areas.

pub mod boundary_flattening;
pub mod circle_domain;
pub mod disk_mobius;
pub mod ellipsoidal_conformal;
pub mod genus_one;
pub mod mobius;
pub mod sea;
pub mod spherical_conformal;
pub mod tutte;
