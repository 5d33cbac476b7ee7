//! Maps of genus-0 closed surfaces onto the unit sphere (SDEM, LSDEM, the spherical conformal
//! map) and onto ellipsoids (EDEM, EDEQ), with the density diffusion, the overlap correction
//! and the input checks they share.

pub(crate) mod density;
pub mod edem;
pub mod edeq;
pub(crate) mod input;
pub mod lsdem;
pub(crate) mod overlap;
pub(crate) mod polish;
pub mod sdem;
pub mod spherical_conformal;
