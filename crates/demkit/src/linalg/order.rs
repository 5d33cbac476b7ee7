//! A fill-reducing elimination order of a mesh's vertices, computed once and shared by every
//! system on that connectivity, whatever vertices each fixes.

use super::{StiffnessPattern, minimum_degree_order};
use crate::Result;

/// An approximate minimum degree order of all the vertices of one connectivity (the pattern
/// of its stiffness matrix with nothing fixed). A system that fixes some vertices eliminates
/// the others in the same order ([`restricted_to`](Self::restricted_to)): removing vertices
/// from a graph does not make its elimination order create more fill, so one analysis serves
/// the spherical conformal map, its south-pole correction and the diffusion operator alike.
#[derive(Debug, Clone)]
pub struct VertexOrder(Vec<usize>);

impl VertexOrder {
    /// The order of the vertices of `faces` on `n_vertices` vertices.
    ///
    /// Errors: a malformed connectivity or a failed ordering.
    pub fn of_mesh(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Self> {
        let pattern = StiffnessPattern::new(n_vertices, faces, None);
        Ok(Self(minimum_degree_order(
            n_vertices,
            pattern.col_ptr(),
            pattern.row_idx(),
        )?))
    }

    /// The order of the unknowns of `pattern` (a pattern of the same connectivity): the
    /// vertices in this order with the fixed ones left out, as unknown indices.
    pub fn restricted_to(&self, pattern: &StiffnessPattern) -> Vec<usize> {
        self.0
            .iter()
            .filter(|&&v| v < pattern.unknown_map().len())
            .filter_map(|&v| pattern.unknown_of(v))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::linalg::SparseCholesky;

    #[test]
    fn the_restricted_order_is_a_permutation_of_the_unknowns() {
        let mesh = icosphere(2).unwrap();
        let n = mesh.n_vertices();
        let order = VertexOrder::of_mesh(n, &mesh.faces).unwrap();
        let fixed: Vec<bool> = (0..n).map(|v| v % 7 == 0).collect();
        let pattern = StiffnessPattern::new(n, &mesh.faces, Some(&fixed));
        let mut r = order.restricted_to(&pattern);
        assert_eq!(r.len(), pattern.n_unknowns());
        // It analyses the system and solves it as the system's own ordering does.
        let chol = SparseCholesky::for_stiffness_in(&pattern, Some(&order));
        assert!(chol.is_ok());
        r.sort_unstable();
        assert!(r.iter().enumerate().all(|(k, &u)| k == u));
    }
}
