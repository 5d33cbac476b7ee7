//! What the maps are for (the papers' applications): texture coordinates so far.

pub mod cartogram;
pub mod texture;
