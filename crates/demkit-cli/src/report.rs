//! The JSON report of `demkit map --report` (DESIGN.md, "Report"; the names are the contract).

use crate::Failure;
use demkit::methods::MapResult;
use demkit::metrics::Metrics;
use serde::Serialize;
use std::path::Path;

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

/// The whole report.
#[derive(Serialize)]
pub struct Report {
    pub method: String,
    pub input: InputSummary,
    pub converged: bool,
    pub stop_reason: String,
    pub iterations: usize,
    pub time_s: Times,
    pub metrics: Metrics,
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
            time_s: Times {
                init: result.time_init,
                map: result.time_map,
                total,
            },
            metrics: metrics.clone(),
            history: result
                .history
                .iter()
                .enumerate()
                .map(|(i, &e)| HistoryEntry {
                    iteration: i + 1,
                    error: e,
                })
                .collect(),
            notes: result.notes.clone(),
        }
    }
}

/// Writes any report as pretty JSON followed by a newline.
pub fn write_json(path: &Path, report: &impl Serialize) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(report).map_err(|e| Failure {
        code: 1,
        message: e.to_string(),
    })?;
    demkit::io::write_bytes_atomically(path, (text + "\n").as_bytes())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))
}
