//! `cushion._cushion`: the compiled core of the Python package `cushion`.
//!
//! Thin by design: Python values are converted to the libraries' types first (scenes, sweep
//! files), the work runs in `cushion-model` and `cushion-sweep` with the GIL released, and the
//! results come back as numpy arrays (handed over without a copy), plain dicts, and Arrow IPC
//! streams that pyarrow turns into pandas frames. The pure-Python layer (`python/cushion/`)
//! builds the user-facing objects (`Run`, DataFrames, plots, Dask).

mod charts;
mod command;
mod convert;
mod design;
mod errors;
mod mcap_read;
mod scene;
mod sensitivity;
mod simulate;
mod sweep;

use pyo3::prelude::*;

#[pymodule]
fn _cushion(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Panics are caught and raised as RuntimeError with their message (errors.rs); the default
    // hook would also print them, with a backtrace, on the user's standard error. This hook
    // belongs to this extension's own copy of the Rust runtime only.
    std::panic::set_hook(Box::new(|_| {}));
    m.add("ConfigError", py.get_type::<errors::ConfigError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The trajectory's column names, the one list the package and the command's CSV share.
    m.add(
        "COLUMNS",
        pyo3::types::PyTuple::new(py, cushion_model::TrajectoryPoint::COLUMNS)?,
    )?;
    // What the command's charts and `cushion.plot` share: figure 3's panels and event lines,
    // and how each quantity is named.
    m.add("FIGURE3", charts::panels(py)?)?;
    m.add("FIGURE3_MARKS", charts::marks(py)?)?;
    m.add("QUANTITIES", charts::quantities(py)?)?;
    m.add_class::<scene::PreparedScene>()?;
    m.add_class::<design::DesignAnswer>()?;
    m.add_function(wrap_pyfunction!(scene::defaults, m)?)?;
    m.add_function(wrap_pyfunction!(scene::keys, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(design::design, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::resolve_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_runs, m)?)?;
    m.add_function(wrap_pyfunction!(mcap_read::read_mcap, m)?)?;
    m.add_function(wrap_pyfunction!(mcap_read::recorded_runs, m)?)?;
    m.add_function(wrap_pyfunction!(command::main, m)?)?;
    m.add_function(wrap_pyfunction!(errors::_panic_guard_check, m)?)?;
    Ok(())
}
