//! The native part of the Python package `demkit` (`demkit._demkit`): numpy arrays in, numpy
//! arrays out, every computation done by the `demkit` library with the GIL released. The
//! Python layer (`python/demkit/__init__.py`) accepts the many input forms and builds the
//! `Map` object; this module sees only C-contiguous float64 and int64 arrays.

mod arrays;
mod mapping;
mod tools;

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    demkit,
    InputError,
    PyValueError,
    "Bad input: a malformed mesh, population, landmark, option or file."
);
create_exception!(
    demkit,
    NumericalError,
    PyRuntimeError,
    "A numerical step failed (not caused by the input), or an internal error."
);

/// The library's error as a Python exception: [`InputError`] for anything the input caused,
/// [`NumericalError`] otherwise. Parameters the library names in backquotes (`` `epsilon` ``)
/// are named plainly, as the keyword arguments spell them.
pub(crate) fn to_py(e: demkit::Error) -> PyErr {
    let message = e.to_string().replace('`', "");
    if e.is_input_error() {
        InputError::new_err(message)
    } else {
        NumericalError::new_err(message)
    }
}

/// A bad-input error with `message`.
pub(crate) fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// Runs `f`, turning a panic (a bug) into a [`NumericalError`] instead of letting it reach
/// Python as a `PanicException`.
pub(crate) fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(NumericalError::new_err(format!(
                "internal error ({msg}); please report it"
            )))
        }
    }
}

/// The module `demkit._demkit`.
#[pymodule]
fn _demkit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // `map` runs on a rayon worker: give the workers an 8 MiB stack, as a main thread has
    // (nothing changes if the process built rayon's pool already).
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(8 << 20)
        .build_global();
    let py = m.py();
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("NumericalError", py.get_type::<NumericalError>())?;
    m.add_function(wrap_pyfunction!(mapping::map, m)?)?;
    m.add_function(wrap_pyfunction!(mapping::remesh, m)?)?;
    m.add_function(wrap_pyfunction!(mapping::methods, m)?)?;
    m.add_function(wrap_pyfunction!(tools::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(tools::write_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(tools::generate, m)?)?;
    m.add_function(wrap_pyfunction!(tools::cut_holes, m)?)?;
    m.add_function(wrap_pyfunction!(tools::metrics, m)?)?;
    m.add_function(wrap_pyfunction!(tools::cartogram, m)?)?;
    Ok(())
}
