//! What the maps are for (the papers' applications): cartograms, registration and texture
//! coordinates.

pub mod cartogram;
pub mod register;
pub mod texture;
