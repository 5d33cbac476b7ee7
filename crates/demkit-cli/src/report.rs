//! The JSON report of `demkit map --report` (DESIGN.md, "Report"; the names are the contract).

use demkit::metrics::Metrics;
use demkit::methods::MapResult;
use serde::Serialize;

/// The input summary.
#[derive(Serialize)]
pub struct InputSummary {
    pub vertices: usize,
    pub faces: usize,
    pub boundaries: usize,
    pub genus: i64,
}

/// Timings in seconds.
#[derive(Serialize)]
pub struct Times {
    pub init: f64,
    pub map: f64,
    pub total: f64,
}

/// One history entry.
#[derive(Serialize)]
pub struct HistoryEntry {
    pub iteration: usize,
    pub error: f64,
}

/// The metrics block.
#[derive(Serialize)]
pub struct MetricsJson {
    pub flipped_triangles: usize,
    pub density_var_initial: f64,
    pub density_var_final: f64,
    pub face_density_var_initial: f64,
    pub face_density_var_final: f64,
    pub density_error_mean: f64,
    pub density_error_sd: f64,
    pub density_median: f64,
    pub density_iqr: f64,
    pub area_ratio_error_mean: f64,
    pub mean_abs_mu: f64,
    pub max_abs_mu: f64,
    pub landmark_error: Option<f64>,
}

impl From<&Metrics> for MetricsJson {
    fn from(m: &Metrics) -> Self {
        MetricsJson {
            flipped_triangles: m.flipped_triangles,
            density_var_initial: m.density_var_initial,
            density_var_final: m.density_var_final,
            face_density_var_initial: m.face_density_var_initial,
            face_density_var_final: m.face_density_var_final,
            density_error_mean: m.density_error_mean,
            density_error_sd: m.density_error_sd,
            density_median: m.density_median,
            density_iqr: m.density_iqr,
            area_ratio_error_mean: m.area_ratio_error_mean,
            mean_abs_mu: m.mean_abs_mu,
            max_abs_mu: m.max_abs_mu,
            landmark_error: m.landmark_error,
        }
    }
}

/// The whole report.
#[derive(Serialize)]
pub struct Report {
    pub method: String,
    pub input: InputSummary,
    pub converged: bool,
    pub stop_reason: String,
    pub iterations: usize,
    pub time_s: Times,
    pub metrics: MetricsJson,
    pub history: Vec<HistoryEntry>,
    pub notes: Vec<String>,
}

impl Report {
    /// Builds the report of a finished run.
    pub fn new(result: &MapResult, input: InputSummary, metrics: &Metrics, total: f64) -> Self {
        Report {
            method: result.method.to_string(),
            input,
            converged: result.converged,
            stop_reason: result.stop_reason.as_str().to_string(),
            iterations: result.iterations,
            time_s: Times { init: result.time_init, map: result.time_map, total },
            metrics: metrics.into(),
            history: result
                .history
                .iter()
                .enumerate()
                .map(|(i, &e)| HistoryEntry { iteration: i + 1, error: e })
                .collect(),
            notes: result.notes.clone(),
        }
    }
}
