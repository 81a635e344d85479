//! One run from Python: the scene built and checked, the run with the GIL released, and its
//! summary, trajectory columns and event log handed back.

use cushion_model::{
    simulate as run_scene, EventLogEntry, RunOptions, RunStatus, Scene, Trajectory, TrajectoryPoint,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

use crate::convert::from_json;
use crate::errors::{config_error, guarded};
use crate::scene::{apply_set, scene_from};

/// Run one scene. Returns `(summary, trajectory, events)`: the summary as the dict of
/// `cushion simulate --json`, the trajectory as [`columns`] (or `None` when not recorded), the
/// event log as [`events`].
#[pyfunction]
#[pyo3(signature = (scene=None, set=None, rtol=None, atol=None, method=None, trajectory=true, sample_interval=None))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    scene: Option<&Bound<'py, PyAny>>,
    set: Option<&Bound<'py, PyDict>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    trajectory: bool,
    sample_interval: Option<f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Events<'py>)> {
    let mut s = scene_from(scene)?;
    apply_set(&mut s, set)?;
    set_solver(&mut s, rtol, atol, method)?;
    s.validate().map_err(config_error)?;
    let recording = RunOptions::recording(&s, sample_interval).map_err(|e| {
        config_error(format!(
            "sample_interval = {}: {e}",
            sample_interval.unwrap_or_default()
        ))
    })?;
    let opts = RunOptions {
        trajectory,
        ..recording
    };
    let result = py.detach(|| guarded("simulate", || run_scene(&s, &opts)))?;
    if result.summary.status == RunStatus::Invalid {
        // The scene passed the checks but the model found it unusable: still bad input.
        return Err(config_error(&result.summary.message));
    }
    let summary = serde_json::to_value(&result.summary)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("summary: {e}")))?;
    let traj = match &result.trajectory {
        Some(t) => columns(py, t)?.into_any(),
        None => py.None().into_bound(py),
    };
    Ok((from_json(py, &summary)?, traj, events(py, &result.events)?))
}

fn set_solver(
    s: &mut Scene,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<()> {
    if let Some(v) = rtol {
        s.set("solver.rtol", &toml::Value::Float(v))
            .map_err(config_error)?;
    }
    if let Some(v) = atol {
        s.set("solver.atol", &toml::Value::Float(v))
            .map_err(config_error)?;
    }
    if let Some(m) = method {
        s.set("solver.method", &toml::Value::String(m.into()))
            .map_err(config_error)?;
    }
    Ok(())
}

/// The event log as handed to Python: times, names, states.
pub type Events<'py> = (Bound<'py, PyAny>, Bound<'py, PyList>, Bound<'py, PyAny>);

/// The trajectory as one `(11, n)` numpy array, a row per column of
/// [`TrajectoryPoint::COLUMNS`] (`t, x_r, ..., F_r`), handed over without a copy: Python takes
/// its rows as views.
pub fn columns<'py>(py: Python<'py>, t: &Trajectory) -> PyResult<Bound<'py, PyAny>> {
    let n = t.points.len();
    let k = TrajectoryPoint::COLUMNS.len();
    let mut data = vec![0.0; k * n];
    for (j, p) in t.points.iter().enumerate() {
        for (i, v) in p.values().into_iter().enumerate() {
            data[i * n + j] = v;
        }
    }
    Ok(PyArray1::from_vec(py, data).reshape([k, n])?.into_any())
}

/// The event log as `(t, names, states)`: the times, the names, and the state at each event as
/// an `(n, 11)` array whose columns are those of the trajectory.
pub fn events<'py>(py: Python<'py>, events: &[EventLogEntry]) -> PyResult<Events<'py>> {
    let k = TrajectoryPoint::COLUMNS.len();
    let t = PyArray1::from_vec(py, events.iter().map(|e| e.t).collect());
    let states: Vec<f64> = events.iter().flat_map(|e| e.point.values()).collect();
    let states = PyArray1::from_vec(py, states).reshape([events.len(), k])?;
    let names = PyList::empty(py);
    for e in events {
        names.append(PyString::new(py, &e.name))?;
    }
    Ok((t.into_any(), names, states.into_any()))
}
