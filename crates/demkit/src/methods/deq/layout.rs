//! The vertex and face numbering DEQ works in, and the hole data it keeps.
//!
//! The surface's faces are split by [`super::rim::peel`] into the *region* (what must lie
//! outside the holes) and the *rims* (ears and peninsulas laid inside the holes). The working
//! numbering puts the region's vertices first, then the vertices only rims use, then any points
//! the hole fillings add; region faces come first, then each hole's faces.

use super::rim::Rims;
use crate::TriMesh;
use crate::geometry::{add, cross, norm, scale, sub};

/// One hole: its peeled loop, its full loop on the surface, and its rim faces.
#[derive(Debug, Clone)]
pub(crate) struct HoleRim {
    /// The peeled loop (working numbering): the hole's circle in the map.
    pub circle_loop: Vec<u32>,
    /// The hole's boundary on the surface (working numbering), rim apexes included; it follows
    /// the face orientation (clockwise around the hole in the plane).
    pub surface_loop: Vec<u32>,
    /// Rim faces peeled into this hole (working numbering) and their input face indices.
    pub rim_faces: Vec<[u32; 3]>,
    pub rim_face_input: Vec<usize>,
    /// Working vertices that only rim faces use (they lie inside the hole).
    pub rim_vertices: Vec<u32>,
    /// The area the hole spans on the surface: `|½ Σ p_k × p_{k+1}|` over its surface loop
    /// (exact for a planar hole, the area of its projection on its best plane otherwise).
    pub surface_area: f64,
    /// The centroid of the surface loop (where a fan filling puts its centre in R³).
    pub surface_centroid: [f64; 3],
}

/// The working numbering of a surface with holes.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// Input vertex of every working vertex (region and rim vertices).
    pub input_vertex: Vec<u32>,
    /// Working vertex of every input vertex.
    pub working_vertex: Vec<u32>,
    /// Region vertices come first: `0..n_region_vertices`.
    pub n_region_vertices: usize,
    /// Region faces (working numbering) and their input indices.
    pub region_faces: Vec<[u32; 3]>,
    pub region_face_input: Vec<usize>,
    /// The outer loop (working numbering), counter-clockwise in the plane.
    pub outer: Vec<u32>,
    /// The holes.
    pub holes: Vec<HoleRim>,
}

impl Layout {
    /// The layout of `mesh` with boundary `loops` (the outer first, as the rims were peeled
    /// with) and the peeled `rims`.
    pub fn new(mesh: &TriMesh, loops: &[Vec<u32>], rims: &Rims) -> Self {
        let n = mesh.n_vertices();
        let mut in_region = vec![false; n];
        for (f, face) in mesh.faces.iter().enumerate() {
            if rims.hole_of_face[f].is_none() {
                for &v in face {
                    in_region[v as usize] = true;
                }
            }
        }
        let mut input_vertex: Vec<u32> = (0..n as u32).filter(|&v| in_region[v as usize]).collect();
        let n_region_vertices = input_vertex.len();
        input_vertex.extend((0..n as u32).filter(|&v| !in_region[v as usize]));
        let mut working_vertex = vec![0u32; n];
        for (w, &v) in input_vertex.iter().enumerate() {
            working_vertex[v as usize] = w as u32;
        }
        let map = |f: &[u32; 3]| f.map(|v| working_vertex[v as usize]);
        let mut region_faces = Vec::new();
        let mut region_face_input = Vec::new();
        let mut holes: Vec<HoleRim> = (1..loops.len())
            .map(|h| {
                let surface: Vec<[f64; 3]> = loops[h]
                    .iter()
                    .map(|&v| mesh.positions[v as usize])
                    .collect();
                HoleRim {
                    circle_loop: rims.loops[h]
                        .iter()
                        .map(|&v| working_vertex[v as usize])
                        .collect(),
                    surface_loop: loops[h]
                        .iter()
                        .map(|&v| working_vertex[v as usize])
                        .collect(),
                    rim_faces: Vec::new(),
                    rim_face_input: Vec::new(),
                    rim_vertices: Vec::new(),
                    surface_area: polygon_vector_area(&surface),
                    surface_centroid: scale(
                        surface.iter().fold([0.0; 3], |s, &p| add(s, p)),
                        1.0 / surface.len() as f64,
                    ),
                }
            })
            .collect();
        for (f, face) in mesh.faces.iter().enumerate() {
            match rims.hole_of_face[f] {
                None => {
                    region_faces.push(map(face));
                    region_face_input.push(f);
                }
                Some(h) => {
                    let hole = &mut holes[h - 1];
                    hole.rim_faces.push(map(face));
                    hole.rim_face_input.push(f);
                    for &v in face {
                        let w = working_vertex[v as usize];
                        if w as usize >= n_region_vertices && !hole.rim_vertices.contains(&w) {
                            hole.rim_vertices.push(w);
                        }
                    }
                }
            }
        }
        let outer = loops[0]
            .iter()
            .map(|&v| working_vertex[v as usize])
            .collect();
        Self {
            input_vertex,
            working_vertex,
            n_region_vertices,
            region_faces,
            region_face_input,
            outer,
            holes,
        }
    }

    /// Number of working vertices of the surface (region and rims).
    pub fn n_surface_vertices(&self) -> usize {
        self.input_vertex.len()
    }

    /// The positions of the surface vertices in input order, from working positions.
    pub fn to_input(&self, working: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; self.input_vertex.len()];
        for (w, &v) in self.input_vertex.iter().enumerate() {
            out[v as usize] = working[w];
        }
        out
    }

    /// The input positions of the surface vertices in working order.
    pub fn from_input(&self, input: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.input_vertex
            .iter()
            .map(|&v| input[v as usize])
            .collect()
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
