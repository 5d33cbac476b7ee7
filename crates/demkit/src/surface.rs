//! [`Surface`]: a validated triangle mesh with its topology, the way into [`crate::map`].

use crate::mesh::topology::{Topology, topology};
use crate::{Result, TriMesh};

/// A triangle mesh that passed validation ([`crate::mesh::validate`]), with its topology
/// computed once. Every method reached through [`crate::map`] takes one, so none sees an index
/// out of range, a non-finite coordinate or a non-manifold edge.
///
/// Coordinates far from unit size (beyond 2^±[`crate::mesh::scale::FREE_RANGE`]) are held
/// scaled by a power of two, exactly; results in input units are scaled back.
#[derive(Debug, Clone)]
pub struct Surface {
    mesh: TriMesh,
    exponent: i32,
    topology: Topology,
    warnings: Vec<String>,
}

impl Surface {
    /// Validates `positions` and `faces` (0-based vertex triples, counter-clockwise). Unused
    /// vertices are dropped, with a warning ([`Surface::warnings`]); any other problem is an
    /// [`crate::Error::InvalidMesh`] naming the first face or vertex at fault.
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self> {
        Self::from_mesh(TriMesh::new(positions, faces))
    }

    /// [`Surface::new`] of a mesh read from a file.
    pub fn from_mesh(mesh: TriMesh) -> Result<Self> {
        let (mut mesh, warnings) = crate::mesh::validate::validate(mesh)?;
        let exponent = crate::mesh::scale::normalizing_exponent(&mesh.positions);
        crate::mesh::scale::scale_positions(&mut mesh.positions, exponent);
        let topology = topology(&mesh);
        Ok(Self {
            mesh,
            exponent,
            topology,
            warnings,
        })
    }

    /// The mesh the methods compute on: the input, scaled by 2^[`Surface::exponent`].
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The input's bounding-box diagonal, in input units.
    pub fn input_diagonal(&self) -> f64 {
        crate::mesh::scale::ldexp(
            crate::geometry::bounding_box_diagonal(&self.mesh.positions),
            -self.exponent,
        )
    }

    /// The power of two the input's coordinates were multiplied by (0 for most inputs).
    pub fn exponent(&self) -> i32 {
        self.exponent
    }

    /// Boundary loops, Euler characteristic, genus and components.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// What validation noticed without refusing the mesh (e.g. dropped unused vertices).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_valid_mesh_becomes_a_surface_and_a_broken_one_an_error() {
        let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [9.0; 3]];
        let s = Surface::new(positions.clone(), vec![[0, 1, 2]]).unwrap();
        assert_eq!(s.mesh().n_vertices(), 3);
        assert_eq!(s.warnings().len(), 1);
        assert_eq!(s.topology().boundary_loops.len(), 1);
        assert_eq!(s.exponent(), 0);
        let e = Surface::new(positions, vec![[0, 1, 7]]).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
    }

    #[test]
    fn a_tiny_mesh_is_held_at_unit_size() {
        let p = vec![[0.0, 0.0, 0.0], [1e-200, 0.0, 0.0], [0.0, 1e-200, 0.0]];
        let s = Surface::new(p, vec![[0, 1, 2]]).unwrap();
        assert!(s.exponent() > 600);
        assert!(s.mesh().positions[1][0] > 0.5 && s.mesh().positions[1][0] < 1.0);
    }
}
