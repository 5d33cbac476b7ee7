//! Shared by the real-mesh tests: where the papers' meshes are, and the lock that keeps the
//! runs of one test binary from overlapping (so the times they print mean something; the
//! budgets are in `benches/`).

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

/// One real mesh at a time: the printed times need the machine to themselves.
pub static SERIAL: Mutex<()> = Mutex::new(());
