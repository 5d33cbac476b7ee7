//! The wall-clock checks of the tests, shared by the unit tests and (through `#[path]`) the
//! integration tests of both crates: the budgets are the issues' figures on an idle 2-core
//! machine, checked only in a release build with `DEMKIT_CHECK_TIME` set (measure them with
//! `DEMKIT_CHECK_TIME=1 cargo test --release -- --ignored --test-threads=1`). CI's shared
//! machines ran the same build up to twice as slow from one run to the next, so there the times
//! are printed, not asserted.
#![allow(dead_code)]

/// Whether the wall-clock budgets are checked.
pub(crate) fn checking_time() -> bool {
    !cfg!(debug_assertions) && std::env::var_os("DEMKIT_CHECK_TIME").is_some()
}

/// Asserts `seconds <= budget` for `what` when [`checking_time`].
pub(crate) fn check_time(what: &str, seconds: f64, budget: f64) {
    if checking_time() {
        assert!(seconds <= budget, "{what}: {seconds:.2} s > {budget} s");
    }
}
