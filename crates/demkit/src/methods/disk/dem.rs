//! DEM: density-equalizing maps of simply connected open surfaces (Choi & Rycroft 2018,
//! Algorithm 5), with recoupling and a bijectivity safeguard (see `planar_diffusion`).
//!
//! Pipeline: planar input is its own initial map; otherwise the boundary is flattened by
//! curvature (Alg. 1) and the interior by the locally authalic map (Alg. 3, falling back to
//! Tutte's map, Alg. 2, when it overlaps). The map is normalised, surrounded by the reflection
//! sea (Alg. 4), and deformed by density diffusion until the density is equal; the sea is
//! dropped and the result rescaled to the input's total area.

use super::input::disk_boundary;
use super::planar_diffusion::{self, Problem};
use crate::geometry::{face_areas, planar_frame, signed_areas_2d};
use crate::init::boundary_flattening::curvature_flatten_boundary;
use crate::init::sea::build_sea_with_radius;
use crate::init::tutte::{InteriorWeights, flatten_with_fallback};
use crate::methods::MethodConfig;
use crate::methods::{MapResult, ProgressFn};
use crate::{Error, Result, TriMesh};
use std::time::Instant;

/// DEM parameters; `Default` gives the paper's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Stop when sd/mean of the (recoupled) vertex density is below ε (paper: 1e-3).
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Time step; `None` uses (4.39).
    pub dt: Option<f64>,
    /// Interior weights of the initial flattening of a non-planar surface (Alg. 2 or 3).
    pub initial: InteriorWeights,
    /// Sea truncation radius η (Alg. 4; paper: 5).
    pub eta: f64,
    /// Radius of the ROI inside the unit disk when the sea is built (Alg. 4 step 1 leaves it
    /// open); 0.85 keeps the sea about 3× the ROI's size.
    pub roi_radius: f64,
    /// Stop as stationary when the best density error has improved by less than 2% over this
    /// many iterations.
    pub patience: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            epsilon: 1e-3,
            max_iter: 500,
            dt: None,
            initial: InteriorWeights::Authalic { lambda: 1.0 },
            eta: 5.0,
            roi_radius: 0.85,
            patience: 5,
        }
    }
}

impl MethodConfig for Config {
    /// Computes the DEM of `mesh` (a topological disk) with one `population` value per face.
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        check_config(self)?;
        let t0 = Instant::now();
        let boundary = disk_boundary(mesh, population, "dem")?;
        let faces = &mesh.faces;
        let mut notes = Vec::new();

        // Alg. 5 lines 1–4: the initial flattening.
        let initial: Vec<[f64; 3]> = match planar_frame(&mesh.positions, faces, 1e-9) {
            Some(frame) => mesh.positions.iter().map(|&p| frame.project(p)).collect(),
            None => {
                let bp = curvature_flatten_boundary(&mesh.positions, &boundary);
                let (map, used) =
                    flatten_with_fallback(&mesh.positions, faces, &boundary, &bp, self.initial)?;
                if used != self.initial {
                    notes.push(
                        "the locally authalic initial map overlapped; used Tutte's map instead"
                            .to_string(),
                    );
                }
                map
            }
        };
        if signed_areas_2d(&initial, faces).iter().any(|&a| !(a > 0.0)) {
            return Err(Error::Numerical(
                "the initial flattening has flipped triangles".into(),
            ));
        }

        // Normalise: area centroid at the origin, total area 1 (scale-free iteration).
        let a0 = face_areas(&initial, faces);
        let area0: f64 = a0.iter().sum();
        let centroid = area_centroid(&initial, faces, &a0);
        let s = 1.0 / area0.sqrt();
        let roi: Vec<[f64; 2]> = initial
            .iter()
            .map(|p| [(p[0] - centroid[0]) * s, (p[1] - centroid[1]) * s])
            .collect();

        // Alg. 4: the sea.
        let sea = build_sea_with_radius(&roi, faces, &boundary, self.eta, self.roi_radius)?;
        let r: Vec<[f64; 3]> = sea.positions.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let areas = face_areas(&r, &sea.faces);
        let total_pop: f64 = population.iter().sum();
        let roi_area: f64 = areas[..sea.n_roi_faces].iter().sum();
        let mean_density = total_pop / roi_area;
        let mut ext_pop = population.to_vec();
        ext_pop.extend(areas[sea.n_roi_faces..].iter().map(|a| mean_density * a));

        let time_init = t0.elapsed().as_secs_f64();

        let t1 = Instant::now();
        let problem = Problem {
            faces: &sea.faces,
            population: ext_pop,
            n_roi_vertices: sea.n_roi_vertices,
            n_roi_faces: sea.n_roi_faces,
            constraint: &super::planar_diffusion::Free,
            dt: self.dt,
            epsilon: self.epsilon,
            max_iter: self.max_iter,
            patience: self.patience,
        };
        let out = planar_diffusion::run(&problem, r, progress)?;

        // Alg. 5 line 18: drop the sea, rescale to the input's total area, keep the initial centroid.
        let result: Vec<[f64; 3]> = out.positions[..sea.n_roi_vertices].to_vec();
        let a1 = face_areas(&result, faces);
        let c1 = area_centroid(&result, faces, &a1);
        let target_area: f64 = face_areas(&mesh.positions, faces).iter().sum();
        let k = (target_area / a1.iter().sum::<f64>()).sqrt();
        let positions = result
            .iter()
            .map(|p| {
                [
                    centroid[0] + (p[0] - c1[0]) * k,
                    centroid[1] + (p[1] - c1[1]) * k,
                    0.0,
                ]
            })
            .collect();
        let mut result = MapResult::new(
            "dem",
            positions,
            initial,
            out.stop_reason,
            out.iterations,
            out.history,
        );
        result.time_init = time_init;
        result.time_map = t1.elapsed().as_secs_f64();
        result.notes = notes;
        Ok(result)
    }
}

fn check_config(c: &Config) -> Result<()> {
    crate::methods::iteration::check_parameters(c.epsilon, c.dt, c.max_iter)?;
    if !(c.eta > 1.0) {
        return Err(Error::Argument(format!(
            "sea radius η must exceed 1, got {}",
            c.eta
        )));
    }
    Ok(())
}

/// Area-weighted centroid of a planar map.
pub(crate) fn area_centroid(map: &[[f64; 3]], faces: &[[u32; 3]], areas: &[f64]) -> [f64; 2] {
    let (mut cx, mut cy, mut s) = (0.0, 0.0, 0.0);
    for (f, &a) in faces.iter().zip(areas) {
        for &v in f {
            cx += a * map[v as usize][0] / 3.0;
            cy += a * map[v as usize][1] / 3.0;
        }
        s += a;
    }
    [cx / s, cy / s]
}
