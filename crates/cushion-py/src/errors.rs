//! Errors as Python sees them: bad input is `cushion.ConfigError` (a `ValueError`) carrying the
//! command line's message, a file problem an `OSError`, a folder in use a `BlockingIOError`, a
//! cancelled sweep `KeyboardInterrupt`, and anything that would have been a Rust panic a
//! `RuntimeError` (never an abort of the interpreter).

use std::panic::{catch_unwind, AssertUnwindSafe};

use cushion_sweep::SweepError;
use pyo3::exceptions::{
    PyBlockingIOError, PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;

pyo3::create_exception!(
    cushion,
    ConfigError,
    PyValueError,
    "Bad input: a scene or sweep key, value or file that the engine refuses. The message names \
     the key, the value and what is allowed; nothing was written."
);

pub fn config_error(msg: impl std::fmt::Display) -> PyErr {
    ConfigError::new_err(msg.to_string())
}

pub fn sweep_error(e: SweepError) -> PyErr {
    match e {
        SweepError::Config(m) => ConfigError::new_err(m),
        SweepError::Busy(m) => PyBlockingIOError::new_err(m),
        SweepError::Io(m) => PyOSError::new_err(m),
        SweepError::Cancelled => PyKeyboardInterrupt::new_err(e.to_string()),
        SweepError::Internal(_) => PyRuntimeError::new_err(e.to_string()),
    }
}

/// Run `f`, turning a panic into a `RuntimeError` with its message.
pub fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| {
        let msg = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown".to_string());
        PyRuntimeError::new_err(format!("internal error in {what}: {msg}"))
    })
}

/// Self-check of the panic guard (used by the test suite): panics inside [`guarded`], so it
/// must raise `RuntimeError`.
#[pyfunction]
pub fn _panic_guard_check() -> PyResult<()> {
    guarded("the panic guard's self-check", || {
        panic!("deliberate panic");
    })
}
