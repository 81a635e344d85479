//! One run from Python: the scene built and checked, the run with the GIL released, and its
//! summary, trajectory columns and event log handed back.

use cushion_model::{
    simulate as run_scene, Cell, EventLogEntry, RunOptions, RunStatus, Scene, Summary, Trajectory,
    TrajectoryPoint,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString};

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
    let traj = match &result.trajectory {
        Some(t) => columns(py, t)?.into_any(),
        None => py.None().into_bound(py),
    };
    let summary = summary_dict(py, &result.summary)?.into_any();
    Ok((summary, traj, events(py, &result.events)?))
}

/// The summary as the dict of `cushion simulate --json`: the cells of [`Summary::COLUMNS`],
/// the `stats_` ones nested under `stats` without the prefix, a float that JSON cannot hold
/// (NaN, infinite) as `None` as JSON writes it (`null`). The keys are made once per process
/// (`tests/python/test_simulate.py::test_summary_equals_the_command_line_json_to_the_bit`).
pub fn summary_dict<'py>(py: Python<'py>, s: &Summary) -> PyResult<Bound<'py, PyDict>> {
    static KEYS: PyOnceLock<Vec<Py<PyString>>> = PyOnceLock::new();
    let keys = KEYS.get_or_init(py, || {
        Summary::COLUMNS
            .iter()
            .map(|c| PyString::intern(py, c.strip_prefix(STATS).unwrap_or(c)).unbind())
            .collect()
    });
    let (top, stats) = (PyDict::new(py), PyDict::new(py));
    for ((column, key), cell) in Summary::COLUMNS.iter().zip(keys).zip(s.cells()) {
        let value = match cell {
            Cell::Float(Some(f)) if f.is_finite() => PyFloat::new(py, f).into_any(),
            Cell::Float(_) => py.None().into_bound(py),
            Cell::Int(i) => i.into_pyobject(py)?.into_any(),
            Cell::Bool(b) => PyBool::new(py, b).to_owned().into_any(),
            Cell::Text(t) => PyString::new(py, &t).into_any(),
        };
        let into = if column.starts_with(STATS) {
            &stats
        } else {
            &top
        };
        into.set_item(key.bind(py), value)?;
    }
    top.set_item(intern!(py, "stats"), stats)?;
    Ok(top)
}

/// The prefix of the solver's counts among [`Summary::COLUMNS`].
const STATS: &str = "stats_";

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
