//! Errors as Python sees them: bad input is `cushion.ConfigError` (a `ValueError`) carrying the
//! command line's message; a file the caller named that cannot be read is Python's own `OSError`
//! subclass for the cause (`FileNotFoundError`, `PermissionError`, `IsADirectoryError`, with
//! `errno` and `filename` set), and any other file problem an `OSError`; a folder in use a `BlockingIOError`, a
//! cancelled sweep `KeyboardInterrupt`, and anything that would have been a Rust panic a
//! `RuntimeError` (never an abort of the interpreter).

use std::io::ErrorKind;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use cushion_sweep::SweepError;
use pyo3::exceptions::{
    PyBlockingIOError, PyFileNotFoundError, PyIsADirectoryError, PyKeyboardInterrupt, PyOSError,
    PyPermissionError, PyRuntimeError, PyValueError,
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

/// Read a file the caller named; a failure is the `OSError` subclass Python's own `open` raises
/// (so `except FileNotFoundError` works), with the path as its `filename`. A file that reads
/// but is not a valid scene or sweep stays a `ConfigError`, raised by whoever parses it.
pub fn read_file(path: &Path) -> PyResult<Vec<u8>> {
    std::fs::read(path).map_err(|e| io_error(path, &e))
}

fn io_error(path: &Path, e: &std::io::Error) -> PyErr {
    let errno = e.raw_os_error().unwrap_or(0);
    // "No such file or directory (os error 2)" -> Python's strerror, "No such file or directory"
    let text = e.to_string();
    let strerror = text
        .split_once(" (os error")
        .map_or(text.as_str(), |(s, _)| s)
        .to_string();
    let args = (errno, strerror, path.display().to_string());
    match e.kind() {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(args),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(args),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(args),
        _ => PyOSError::new_err(args),
    }
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
