//! What the maps are for (the papers' applications): remeshing, cartograms, registration and
//! texture coordinates.

pub mod cartogram;
pub mod register;
pub mod remesh;
pub mod texture;
