//! Maps onto a torus: TDEM.

pub mod tdem;
