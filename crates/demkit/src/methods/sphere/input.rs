//! Input checks and the initial map shared by the spherical methods.

use crate::init::mobius::mobius_area_correction;
use crate::init::spherical_conformal::spherical_conformal_map_in_order;
use crate::linalg::VertexOrder;
use crate::mesh::Locality;
use crate::mesh::topology::topology;
use crate::methods::iteration::check_parameters;
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

/// A genus-0 closed surface checked for a spherical or ellipsoidal method (SDEM, EDEM, EDEQ),
/// renumbered for a cache-friendly traversal ([`Locality`]), with its elimination order.
pub(crate) struct SphereInput {
    /// The renumbering; it restores the input's vertex order at the end.
    pub local: Locality,
    /// The renumbered mesh.
    pub mesh: TriMesh,
    /// The population, one value per face of the renumbered mesh.
    pub population: Vec<f64>,
    /// The fill-reducing order shared by every factorization on the mesh.
    pub order: VertexOrder,
}

impl SphereInput {
    /// Checks the flow's parameters ([`check_parameters`]) and the input
    /// ([`check_sphere_input`]) for `method`, then renumbers the mesh and orders it.
    pub(crate) fn new(
        mesh: &TriMesh,
        population: &[f64],
        flow: &super::sdem::Config,
        method: &str,
    ) -> Result<Self> {
        check_parameters(flow.epsilon, flow.dt, flow.max_iter)?;
        check_sphere_input(mesh, population, method)?;
        let local = Locality::breadth_first(mesh.n_vertices(), &mesh.faces);
        let (mesh, population) = (local.mesh(mesh), local.faces(population));
        let order = VertexOrder::of_mesh(mesh.n_vertices(), &mesh.faces)?;
        Ok(Self {
            local,
            mesh,
            population,
            order,
        })
    }

    /// The renumbering, the mesh, its population and its order, borrowed together.
    pub(crate) fn parts(&self) -> (&Locality, &TriMesh, &[f64], &VertexOrder) {
        (&self.local, &self.mesh, &self.population, &self.order)
    }
}
