//! The JSON report of a map (DESIGN.md, "Report"): the names of its fields are the contract
//! shared by `demkit map --report` and the Python package's `Map.report`.

use crate::api::Map;
use crate::metrics::Metrics;
use crate::{Surface, TriMesh};
use serde::Serialize;

/// A mesh's size and topology, as the report gives them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InputSummary {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of boundary loops.
    pub boundaries: usize,
    /// Genus.
    pub genus: i64,
}

impl InputSummary {
    /// The summary of a validated surface (its topology is already known).
    pub fn of_surface(surface: &Surface) -> Self {
        let mesh = surface.mesh();
        let topology = surface.topology();
        InputSummary {
            vertices: mesh.n_vertices(),
            faces: mesh.n_faces(),
            boundaries: topology.boundary_loops.len(),
            genus: topology.genus,
        }
    }

    /// The summary of any mesh (its topology computed here).
    pub fn of_mesh(mesh: &TriMesh) -> Self {
        let topology = crate::mesh::topology::topology(mesh);
        InputSummary {
            vertices: mesh.n_vertices(),
            faces: mesh.n_faces(),
            boundaries: topology.boundary_loops.len(),
            genus: topology.genus,
        }
    }
}

/// Timings in seconds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Times {
    /// The initial map.
    pub init: f64,
    /// The density-equalizing iteration.
    pub map: f64,
    /// Everything the caller counts (reading, mapping, writing for the command line).
    pub total: f64,
}

/// One iteration's stopping quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistoryEntry {
    /// 1-based iteration number.
    pub iteration: usize,
    /// The method's own stopping quantity after it.
    pub error: f64,
}

/// The whole report of a map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The method's report name (`"sdem"`, ...).
    pub method: String,
    /// The input surface.
    pub input: InputSummary,
    /// Where the map lies: `"plane"`, `"circle-domain"`, `"sphere"`, `"ellipsoid"` or
    /// `"torus"`.
    pub domain: String,
    /// The ellipsoid's radii `[a, b, c]`, for maps onto an ellipsoid (EDEQ's are the ones it
    /// chose).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radii: Option<[f64; 3]>,
    /// False when the iteration limit ran out.
    pub converged: bool,
    /// `"tolerance"`, `"stationary"` or `"max_iter"`.
    pub stop_reason: String,
    /// Number of iterations done.
    pub iterations: usize,
    /// Timings.
    pub time_s: Times,
    /// The metrics (DESIGN.md, "Report").
    pub metrics: Metrics,
    /// One entry per iteration.
    pub history: Vec<HistoryEntry>,
    /// Remarks of the method worth telling the user.
    pub notes: Vec<String>,
}

impl Map {
    /// The report of this map of `surface`; `total` is the time in seconds the caller counts as
    /// the whole run.
    pub fn report(&self, surface: &Surface, total: f64) -> Report {
        let result = &self.result;
        Report {
            method: result.method.to_string(),
            input: InputSummary::of_surface(surface),
            domain: self.domain.name().to_string(),
            radii: match self.domain {
                crate::Domain::Ellipsoid { a, b, c } => Some([a, b, c]),
                _ => None,
            },
            converged: result.converged,
            stop_reason: result.stop_reason.as_str().to_string(),
            iterations: result.iterations,
            time_s: Times {
                init: result.time_init,
                map: result.time_map,
                total,
            },
            metrics: self.metrics.clone(),
            history: result
                .history
                .iter()
                .enumerate()
                .map(|(i, &error)| HistoryEntry {
                    iteration: i + 1,
                    error,
                })
                .collect(),
            notes: result.notes.clone(),
        }
    }
}
