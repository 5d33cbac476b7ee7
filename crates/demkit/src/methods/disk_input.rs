//! Input checks shared by the disk methods: topology, population length.

use crate::mesh::topology::topology;
use crate::{Error, Result, TriMesh};

/// Checks that `mesh` is a simply connected open surface (one boundary loop, genus 0, one
/// component) and `population` has one value per face; returns the boundary loop
/// (counter-clockwise with respect to the face orientation).
pub(crate) fn disk_boundary(mesh: &TriMesh, population: &[f64], method: &str) -> Result<Vec<u32>> {
    super::require_valid_mesh(mesh, method)?;
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

/// (4.39): `δt = min(min ρ / mean ρ, mean ρ / max ρ) × Area`, from the initial vertex density.
pub(crate) fn default_time_step(rho_v: &[f64], area: f64) -> f64 {
    let n = rho_v.len() as f64;
    let mean = rho_v.iter().sum::<f64>() / n;
    let min = rho_v.iter().cloned().fold(f64::INFINITY, f64::min);
    let max = rho_v.iter().cloned().fold(0.0, f64::max);
    (min / mean).min(mean / max) * area
}
