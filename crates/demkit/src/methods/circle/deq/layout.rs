//! The boundary of a surface with holes as DEQ works with it: the outer loop, and for every
//! hole its loop and what the hole spans on the surface.

use crate::TriMesh;
use crate::geometry::{add, cross, norm, scale, sub};

/// One hole.
#[derive(Debug, Clone)]
pub(crate) struct Hole {
    /// The hole's loop; it follows the face orientation (clockwise around the hole in the
    /// plane). It has no chord ([`super::chords`]), so it can lie on the hole's circle.
    pub boundary: Vec<u32>,
    /// The area the hole spans on the surface: `|½ Σ p_k × p_{k+1}|` over its loop (exact for
    /// a planar hole, the area of its projection on its best plane otherwise).
    pub surface_area: f64,
    /// The centroid of the loop (where a fan filling puts its centre in R³).
    pub surface_centroid: [f64; 3],
}

/// The loops of a surface with holes.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// The outer loop, counter-clockwise in the plane.
    pub outer: Vec<u32>,
    /// The holes.
    pub holes: Vec<Hole>,
}

impl Layout {
    /// The layout of `mesh` with boundary `loops`, the outer one first.
    pub fn new(mesh: &TriMesh, loops: &[Vec<u32>]) -> Self {
        let holes = loops[1..]
            .iter()
            .map(|lp| {
                let surface: Vec<[f64; 3]> =
                    lp.iter().map(|&v| mesh.positions[v as usize]).collect();
                Hole {
                    boundary: lp.clone(),
                    surface_area: polygon_vector_area(&surface),
                    surface_centroid: scale(
                        surface.iter().fold([0.0; 3], |s, &p| add(s, p)),
                        1.0 / surface.len() as f64,
                    ),
                }
            })
            .collect();
        Self {
            outer: loops[0].clone(),
            holes,
        }
    }

    /// For each of the `n` vertices, whether it lies on a loop (the outer one or a hole's):
    /// the vertices a circle domain map holds on its circles.
    pub fn on_loops(&self, n: usize) -> Vec<bool> {
        let mut on = vec![false; n];
        for &v in self
            .outer
            .iter()
            .chain(self.holes.iter().flat_map(|h| h.boundary.iter()))
        {
            on[v as usize] = true;
        }
        on
    }
}

/// `|½ Σ_k (p_k − p_0) × (p_{k+1} − p_0)|`: the area a closed polygon in R³ spans.
pub(crate) fn polygon_vector_area(p: &[[f64; 3]]) -> f64 {
    let mut sum = [0.0; 3];
    for k in 1..p.len().saturating_sub(1) {
        sum = add(sum, cross(sub(p[k], p[0]), sub(p[k + 1], p[0])));
    }
    0.5 * norm(sum)
}
