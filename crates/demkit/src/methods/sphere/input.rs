//! Input checks and the initial map shared by the spherical methods.

use crate::init::mobius::mobius_area_correction;
use crate::init::spherical_conformal::spherical_conformal_map_in_order;
use crate::linalg::VertexOrder;
use crate::mesh::topology::topology;
use crate::{Error, Result, TriMesh};

/// Checks that `mesh` is a genus-0 closed surface (no boundary, one component) and that
/// `population` has one positive value per face.
pub(crate) fn check_sphere_input(mesh: &TriMesh, population: &[f64], method: &str) -> Result<()> {
    crate::methods::require_valid_mesh(mesh, method)?;
    let topo = topology(mesh);
    if topo.components != 1 || !topo.boundary_loops.is_empty() || topo.genus != 0 {
        let what = if topo.components != 1 {
            format!("a mesh with {} components", topo.components)
        } else if topo.boundary_loops.is_empty() {
            format!("a closed surface of genus {}", topo.genus)
        } else {
            format!(
                "an open surface with {} boundary loop{} and genus {}",
                topo.boundary_loops.len(),
                if topo.boundary_loops.len() == 1 {
                    ""
                } else {
                    "s"
                },
                topo.genus
            )
        };
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!(
                "{method} needs a genus-0 closed surface (no boundary, one component), but this is {what}"
            ),
        });
    }
    crate::population::check_population(population, mesh.n_faces())
}

/// The initial map of SDEM and LSDEM (§3.1.1): the spherical conformal map composed with the
/// Möbius transformation that best matches the map's face areas to `population` (with the
/// population `area` this is the Möbius area correction; with any other population it starts
/// the diffusion closer to equal density, and the map stays conformal).
/// `order` is the mesh's elimination order, shared with the diffusion operator.
pub(crate) fn initial_sphere_map(
    mesh: &TriMesh,
    population: &[f64],
    order: &VertexOrder,
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>> {
    let conformal = spherical_conformal_map_in_order(&mesh.positions, &mesh.faces, order, notes)?;
    Ok(mobius_area_correction(&conformal, &mesh.faces, population).map)
}
