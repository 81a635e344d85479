//! A recorded run read back from an MCAP file (`cushion simulate --mcap`, or a sweep's
//! `trajectories.mcap`).

use cushion_sweep::mcap_read::{read_run, recorded_runs as runs_in, ReadError};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;

use crate::errors::{config_error, read_file};
use crate::simulate::{columns, events, Events};

fn read(path: &str) -> PyResult<Vec<u8>> {
    read_file(std::path::Path::new(path))
}

fn mcap_error(path: &str, e: ReadError) -> PyErr {
    match e {
        ReadError::NoSuchRun { .. } => config_error(format!("{path}: {e}")),
        _ => PyOSError::new_err(format!("{path}: {e}")),
    }
}

/// `(trajectory, events)` of one recorded run, as `simulate` returns them.
#[pyfunction]
#[pyo3(signature = (path, run=None))]
pub fn read_mcap<'py>(
    py: Python<'py>,
    path: &str,
    run: Option<u64>,
) -> PyResult<(Bound<'py, PyAny>, Events<'py>)> {
    let bytes = read(path)?;
    let (traj, evs) = py
        .detach(|| read_run(&bytes, run))
        .map_err(|e| mcap_error(path, e))?;
    Ok((columns(py, &traj)?, events(py, &evs)?))
}

/// The run numbers recorded in a sweep's MCAP file.
#[pyfunction]
pub fn recorded_runs(path: &str) -> PyResult<Vec<u64>> {
    let bytes = read(path)?;
    runs_in(&bytes).map_err(|e| mcap_error(path, e))
}
