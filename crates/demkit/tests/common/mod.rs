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
