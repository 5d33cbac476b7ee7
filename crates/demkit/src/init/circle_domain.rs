//! Placeholder: the circle-domain conformal map arrives on its own branch.

use crate::{Error, Result, TriMesh};

/// A circle domain: the unit disk minus k disjoint disks.
#[derive(Debug, Clone)]
pub struct CircleDomain {
    /// Planar image of every vertex (z = 0), counter-clockwise (positive signed areas).
    pub positions: Vec<[f64; 3]>,
    /// Boundary loops as vertex lists: [0] the outer loop (on the unit circle, centre 0), then the holes.
    pub loops: Vec<Vec<u32>>,
    /// Centre of each loop's circle (loops[0]: [0,0]).
    pub centers: Vec<[f64; 2]>,
    /// Radius of each loop's circle (loops[0]: 1).
    pub radii: Vec<f64>,
}

/// Not yet.
pub fn circle_domain_map(_mesh: &TriMesh, _loops: &[Vec<u32>]) -> Result<CircleDomain> {
    Err(Error::Numerical("circle domain map not available".into()))
}
