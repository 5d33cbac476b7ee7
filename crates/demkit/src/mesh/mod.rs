//! Triangle meshes: the [`TriMesh`] type, topology, validation, welding, edge splitting,
//! midpoint subdivision and holes cut around points.

pub mod holes;
pub(crate) mod locality;
pub mod scale;
pub mod split;
pub mod subdivide;
pub mod topology;
pub mod triangulate;
pub(crate) mod union_find;
pub mod validate;
pub mod weld;

pub use holes::{Hole, cut_holes};
pub(crate) use locality::Locality;
pub use subdivide::{
    split_population, split_population_parts, subdivide, subdivide_levels, subdivide_parts,
};
pub use topology::{Topology, connected_components, edges, topology, vertex_faces};
pub use validate::{Findings, check, validate};
pub use weld::weld;

/// A triangle mesh: vertex positions and faces (counter-clockwise vertex triples).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions in R^3 (planar meshes have z = 0).
    pub positions: Vec<[f64; 3]>,
    /// Faces as triples of 0-based vertex indices.
    pub faces: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Builds a mesh from positions and faces without any check.
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Self {
        Self { positions, faces }
    }
    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.faces.len()
    }
    /// The three corner positions of face `f`.
    pub fn corners(&self, f: usize) -> [[f64; 3]; 3] {
        let [a, b, c] = self.faces[f];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }
}
