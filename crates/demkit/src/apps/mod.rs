//! What the maps are for (the papers' applications): texture coordinates and remeshing.

pub mod remesh;
pub mod texture;
