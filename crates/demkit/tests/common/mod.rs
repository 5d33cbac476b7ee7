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

/// Whether the wall-clock budgets are checked: only when `DEMKIT_CHECK_TIME` is set, in a
/// release build. The budgets are the issues' figures on an idle 2-core machine (measure them with
/// `DEMKIT_CHECK_TIME=1 cargo test --release -- --ignored --test-threads=1`); CI's shared machines
/// ran the same build up to twice as slow from one run to the next, so CI prints the times and
/// leaves the budgets to that idle measurement.
#[allow(dead_code)]
pub fn checking_time() -> bool {
    !cfg!(debug_assertions) && std::env::var_os("DEMKIT_CHECK_TIME").is_some()
}

/// Asserts `elapsed <= seconds` for `what` when [`checking_time`].
#[allow(dead_code)]
pub fn check_time(what: &str, elapsed: f64, seconds: f64) {
    if checking_time() {
        assert!(elapsed <= seconds, "{what}: {elapsed:.2} s > {seconds} s");
    }
}
