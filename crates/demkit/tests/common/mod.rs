//! Shared by the real-mesh tests: where the papers' meshes are, and the lock that keeps the
//! timed runs of one test binary from overlapping.

use std::path::PathBuf;
use std::sync::Mutex;

/// A file of the real-mesh data folder: `DEMKIT_DATA`, default `../shared/data` beside the
/// checkout.
pub fn data(rel: &str) -> PathBuf {
    let root = std::env::var_os("DEMKIT_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    root.join(rel)
}

/// The timing checks need the machine to themselves: one real mesh at a time.
pub static SERIAL: Mutex<()> = Mutex::new(());

/// A time budget as the timing checks apply it: `seconds` times `DEMKIT_TIME_SCALE` (default
/// 1). The budgets are the issues' figures on an idle 2-core machine; `.ci/run` sets the scale
/// for the shared machines CI runs on, whose speed varies from run to run.
#[allow(dead_code)]
pub fn budget(seconds: f64) -> f64 {
    let scale = std::env::var("DEMKIT_TIME_SCALE")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| *s >= 1.0)
        .unwrap_or(1.0);
    seconds * scale
}
