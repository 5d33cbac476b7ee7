//! What the maps are for (the papers' applications): registration, remeshing and texture
//! coordinates.

pub mod register;
pub mod remesh;
pub mod texture;
