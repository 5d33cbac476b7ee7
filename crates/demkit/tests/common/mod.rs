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

/// The wall-clock budgets: printed always, asserted with `DEMKIT_CHECK_TIME` (see the file).
#[path = "../../src/test_timing.rs"]
mod timing;
#[allow(unused_imports)]
pub(crate) use timing::{check_time, checking_time};
