//! Sensitivity studies from Python: `cushion.sensitivity(config)` runs a saltelli sweep (a file
//! path or a dict of the file's shape) through the same engine and analysis as `cushion
//! sensitivity`, with the GIL released and Ctrl-C looked for between runs (as `sweep` and
//! `design` do), and hands back the long table as an Arrow IPC stream. With `out`, every file
//! of the command is written there too.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use cushion_cli::sensitivity::{prepare, run_in_memory, run_to_folder, Failure};
use cushion_sensitivity::study::long_table;
use cushion_sweep::{Hooks, SweepFile, SweepOptions};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::file_config;
use crate::errors::{config_error, sweep_error};
use crate::sweep::{ipc_bytes, run_detached};

/// The saltelli sweep a user gave: a path to a sweep file, or a dict of the same shape.
fn sweep_from(config: &Bound<'_, PyAny>) -> PyResult<SweepFile> {
    file_config(
        config,
        "sweep",
        "sensitivity",
        SweepFile::from_file,
        SweepFile::from_str_at,
    )
}

/// Run a saltelli sweep and analyse it: the long table (the columns of `sensitivity.parquet`)
/// as an Arrow IPC stream. `outputs` overrides `[sensitivity] outputs`; `resume` continues the
/// unfinished study in `out`.
#[pyfunction]
#[pyo3(signature = (config, outputs=None, threads=None, out=None, resume=false, progress=None, git_commit=None))]
#[allow(clippy::too_many_arguments)]
pub fn sensitivity<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
    outputs: Option<Vec<String>>,
    threads: Option<usize>,
    out: Option<PathBuf>,
    resume: bool,
    progress: Option<&Bound<'py, PyAny>>,
    git_commit: Option<String>,
) -> PyResult<Bound<'py, PyBytes>> {
    let sweep = sweep_from(config)?;
    if resume && out.is_none() {
        return Err(config_error(
            "resume=True needs out: the folder of the study to continue",
        ));
    }
    if threads == Some(0) {
        return Err(config_error(
            "threads = 0: must be at least 1 (or None for every core)",
        ));
    }
    let prep = prepare(sweep, outputs).map_err(sweep_error)?;
    let cancel = AtomicBool::new(false);
    let counts = (AtomicU64::new(0), AtomicU64::new(0));
    let on_progress = |done: u64, total: u64| {
        counts.0.store(done, Ordering::Relaxed);
        counts.1.store(total, Ordering::Relaxed);
    };
    let hooks = Hooks {
        progress: Some(&on_progress),
        cancel: Some(&cancel),
        chunk_written: None,
    };
    // A failed-runs stop is not an error of the sweep: it comes back as the inner result.
    let study = run_detached(py, &cancel, &counts, progress, || {
        let done = match out {
            None => run_in_memory(prep, threads, &hooks),
            Some(dir) => {
                let opts = SweepOptions {
                    out: Some(dir),
                    threads,
                    resume,
                    shard: None,
                    git_commit,
                };
                run_to_folder(prep, &opts, &hooks).map(|(_, study, _)| study)
            }
        };
        match done {
            Ok(study) => Ok(Ok(study)),
            Err(Failure::Sweep(e)) => Err(e),
            Err(Failure::FailedRuns(m)) => Ok(Err(m)),
        }
    })?
    .map_err(pyo3::exceptions::PyRuntimeError::new_err)?;
    let table = long_table(&study);
    ipc_bytes(py, std::slice::from_ref(&table), table.schema())
}
