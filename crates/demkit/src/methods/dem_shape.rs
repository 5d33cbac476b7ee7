//! Shape-prescribed DEM (Choi & Rycroft 2018, Algorithm 6): Tutte's map onto the shape with an
//! arclength-parameterized boundary, no sea, and boundary vertices projected back onto the
//! shape after every step (they slide along it). Recoupling and the bijectivity safeguard as in
//! DEM. The result stays in the shape's own coordinates (no final rescale), so the boundary lies
//! exactly on the prescribed curve.

use super::dem::check_config_values;
use super::disk_input::{default_time_step, disk_boundary};
use super::planar_diffusion::{self, Problem};
use super::{MapResult, ProgressFn};
use crate::fem::VertexFaces;
use crate::geometry::{face_areas, norm, sub};
use crate::init::shape::Shape;
use crate::init::tutte::{fixed_boundary_map, InteriorWeights};
use crate::{Result, TriMesh};
use std::time::Instant;

/// Shape-prescribed DEM parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The target boundary shape.
    pub shape: Shape,
    /// Stop when sd/mean of the (recoupled) vertex density is below ε.
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Time step; `None` uses (4.39).
    pub dt: Option<f64>,
    /// Iterations without improvement before stopping as stationary.
    pub patience: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self { shape: Shape::Disk, epsilon: 1e-3, max_iter: 500, dt: None, patience: 5 }
    }
}

/// Computes the shape-prescribed DEM of `mesh` (a topological disk).
pub fn run(mesh: &TriMesh, population: &[f64], config: &Config, progress: ProgressFn) -> Result<MapResult> {
    check_config_values(config.epsilon, config.dt, config.max_iter)?;
    let t0 = Instant::now();
    let boundary = disk_boundary(mesh, population, "dem-shape")?;
    let faces = &mesh.faces;
    let lengths: Vec<f64> = (0..boundary.len())
        .map(|k| {
            let a = mesh.positions[boundary[k] as usize];
            let b = mesh.positions[boundary[(k + 1) % boundary.len()] as usize];
            norm(sub(b, a))
        })
        .collect();
    let bp = config.shape.boundary_positions(&lengths);
    let initial = fixed_boundary_map(&mesh.positions, faces, &boundary, &bp, InteriorWeights::Tutte)?;
    let areas = face_areas(&initial, faces);
    let area: f64 = areas.iter().sum();
    let dt = match config.dt {
        Some(dt) => dt,
        None => {
            let rho_f: Vec<f64> = population.iter().zip(&areas).map(|(p, a)| p / a).collect();
            let rho_v = VertexFaces::new(mesh.n_vertices(), faces).apply(&areas, &rho_f);
            default_time_step(&rho_v, area)
        }
    };
    let time_init = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let problem = Problem {
        faces,
        population: population.to_vec(),
        n_roi_vertices: mesh.n_vertices(),
        n_roi_faces: mesh.n_faces(),
        shape: Some((boundary, config.shape)),
        dt,
        adaptive_dt: config.dt.is_none(),
        epsilon: config.epsilon,
        max_iter: config.max_iter,
        patience: config.patience,
    };
    let out = planar_diffusion::run(&problem, initial.clone(), progress)?;
    Ok(MapResult {
        method: "dem-shape",
        positions: out.positions,
        initial,
        converged: out.stop_reason != super::StopReason::MaxIter,
        stop_reason: out.stop_reason,
        iterations: out.iterations,
        history: out.history,
        time_init,
        time_map: t1.elapsed().as_secs_f64(),
        notes: Vec::new(),
    })
}
