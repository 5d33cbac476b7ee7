//! Maps onto the unit sphere: SDEM, LSDEM and the spherical conformal map, with the density
//! diffusion, the overlap correction and the input checks they share.

pub(crate) mod density;
pub(crate) mod input;
pub mod lsdem;
pub(crate) mod overlap;
pub mod sdem;
pub mod spherical_conformal;
