//! The wall-clock checks of the unit tests, as the integration tests apply them
//! (`tests/common`): the budgets are figures on an idle 2-core machine, checked only in a
//! release build with `DEMKIT_CHECK_TIME` set; CI's shared machines vary twofold from run to
//! run, so there the times are printed, not asserted.

/// Asserts `seconds <= budget` for `what` when the budgets are checked.
pub(crate) fn check_time(what: &str, seconds: f64, budget: f64) {
    if !cfg!(debug_assertions) && std::env::var_os("DEMKIT_CHECK_TIME").is_some() {
        assert!(seconds <= budget, "{what}: {seconds:.3} s > {budget} s");
    }
}
