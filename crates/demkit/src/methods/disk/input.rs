//! Input checks shared by the disk methods: topology, population length.

use crate::mesh::topology::topology;
use crate::{Error, Result, TriMesh};

/// Checks that `mesh` is a simply connected open surface (one boundary loop, genus 0, one
/// component) and `population` has one value per face; returns the boundary loop
/// (counter-clockwise with respect to the face orientation).
pub(crate) fn disk_boundary(mesh: &TriMesh, population: &[f64], method: &str) -> Result<Vec<u32>> {
    crate::methods::require_valid_mesh(mesh, method)?;
    let topo = topology(mesh);
    if topo.components != 1 || topo.boundary_loops.len() != 1 || topo.genus != 0 {
        let what = if topo.boundary_loops.is_empty() {
            format!("a closed surface of genus {}", topo.genus)
        } else {
            format!(
                "a surface with {} boundary loops and genus {}",
                topo.boundary_loops.len(),
                topo.genus
            )
        };
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!(
                "{method} needs a simply connected open surface (one boundary loop, genus 0), but this is {what}"
            ),
        });
    }
    crate::population::check_population(population, mesh.n_faces())?;
    Ok(topo.boundary_loops.into_iter().next().unwrap_or_default())
}
