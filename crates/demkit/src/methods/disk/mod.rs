//! Maps onto the plane: DEM with a free boundary and onto a prescribed shape, and the planar
//! density-equalizing flow they share (with DEQ's flow on its filled disk).

pub mod dem;
pub mod dem_shape;
pub(crate) mod input;
pub(crate) mod planar_diffusion;
