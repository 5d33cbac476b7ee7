//! What the maps are for (the papers' applications): registration and texture coordinates.

pub mod register;
pub mod texture;
