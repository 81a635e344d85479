//! Sweeps from Python. The sweep (a file path or a dict of the file's shape) is parsed first,
//! then run by `cushion-sweep` with the GIL released; this thread waits for it, and between
//! waits takes the GIL to report progress and to look for Ctrl-C, which raises the engine's
//! cancel flag (the sweep stops within one chunk, keeping its finished chunks for `resume`).
//! The rows come back as an Arrow IPC stream, which pyarrow reads into a table.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use arrow_array::RecordBatch;
use cushion_sweep::engine::{compute, Hooks, Plan};
use cushion_sweep::parquet_io::read_parquet_all;
use cushion_sweep::{run_sweep, Runs, SweepError, SweepFile, SweepOptions};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::file_config;
use crate::errors::{config_error, guarded, sweep_error};

/// How often the waiting thread reports progress and looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(100);

/// The sweep a user gave: a path to a sweep file, or a dict of the same shape.
fn sweep_from(config: &Bound<'_, PyAny>) -> PyResult<SweepFile> {
    file_config(
        config,
        "sweep",
        "sweep",
        SweepFile::from_file,
        SweepFile::from_str_at,
    )
}

/// Run `work` on another thread with the GIL released. Meanwhile, at most every [`POLL`], call
/// `progress(done, total)` and look for a pending signal; on one (Ctrl-C), raise `cancel` and
/// re-raise the signal's exception once `work` has stopped.
pub(crate) fn run_detached<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    counts: &(AtomicU64, AtomicU64),
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> Result<T, SweepError> + Send,
) -> PyResult<T> {
    let progress = progress.map(|p| p.clone().unbind());
    let report = |py: Python<'_>| -> PyResult<()> {
        if let Some(p) = &progress {
            let (done, total) = (
                counts.0.load(Ordering::Relaxed),
                counts.1.load(Ordering::Relaxed),
            );
            p.call1(py, (done, total))?;
        }
        Ok(())
    };
    let (result, interrupt) = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel();
            s.spawn(move || {
                let _ = tx.send(guarded("sweep", work));
            });
            let mut interrupt: Option<PyErr> = None;
            loop {
                match rx.recv_timeout(POLL) {
                    Ok(r) => break (r, interrupt),
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        Python::attach(|py| {
                            if interrupt.is_none() {
                                if let Err(e) = py.check_signals().and_then(|_| report(py)) {
                                    cancel.store(true, Ordering::SeqCst);
                                    interrupt = Some(e);
                                }
                            }
                        });
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        break (
                            Err(pyo3::exceptions::PyRuntimeError::new_err(
                                "the sweep thread ended without a result",
                            )),
                            interrupt,
                        )
                    }
                }
            }
        })
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    let value = result?.map_err(sweep_error)?;
    report(py)?;
    Ok(value)
}

/// Record batches as one Arrow IPC stream.
pub(crate) fn ipc_bytes<'py>(
    py: Python<'py>,
    batches: &[RecordBatch],
    plan_schema: arrow_schema::SchemaRef,
) -> PyResult<Bound<'py, PyBytes>> {
    let mut buf = Vec::new();
    {
        let mut w = arrow_ipc::writer::StreamWriter::try_new(&mut buf, &plan_schema)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("Arrow IPC: {e}")))?;
        for b in batches {
            w.write(b).map_err(|e| {
                pyo3::exceptions::PyRuntimeError::new_err(format!("Arrow IPC: {e}"))
            })?;
        }
        w.finish()
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("Arrow IPC: {e}")))?;
    }
    Ok(PyBytes::new(py, &buf))
}

/// Run a sweep; its summary rows as an Arrow IPC stream (the columns of `summary.parquet`).
/// With `out`, every file of `cushion sweep` is written there too (and `resume` continues an
/// unfinished one).
#[pyfunction]
#[pyo3(signature = (config, threads=None, out=None, resume=false, progress=None, git_commit=None))]
pub fn sweep<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
    threads: Option<usize>,
    out: Option<PathBuf>,
    resume: bool,
    progress: Option<&Bound<'py, PyAny>>,
    git_commit: Option<String>,
) -> PyResult<Bound<'py, PyBytes>> {
    let sweep = sweep_from(config)?;
    if resume && out.is_none() {
        return Err(config_error(
            "resume=True needs out: the folder of the sweep to continue",
        ));
    }
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
    let schema = cushion_sweep::summary_table::TableSchema::new(&sweep.axes).arrow;
    let batches = run_detached(py, &cancel, &counts, progress, || match out {
        None => {
            let plan = Plan::new(sweep)?;
            let n = plan.n_runs();
            compute(&plan, Runs::all(n), threads, &hooks)
        }
        Some(dir) => {
            let opts = SweepOptions {
                out: Some(dir),
                threads,
                resume,
                shard: None,
                git_commit,
            };
            let o = run_sweep(sweep, &opts, &hooks)?;
            read_parquet_all(&o.out_dir.join("summary.parquet"))
        }
    })?;
    ipc_bytes(py, &batches, schema)
}

/// The sweep as self-contained TOML text (its base scene written out in full, `[set]` applied),
/// which runs anywhere without the files it named, and its run count.
#[pyfunction]
pub fn resolve_sweep(config: &Bound<'_, PyAny>) -> PyResult<(String, u64)> {
    let sweep = sweep_from(config)?;
    let mut table: toml::Table = sweep
        .text
        .parse()
        .map_err(|e| config_error(format!("sweep config: {e}")))?;
    table.insert("scene".into(), toml::Value::Table(sweep.base.to_toml()));
    table.remove("set");
    table.insert("name".into(), toml::Value::String(sweep.name.clone()));
    let text = toml::to_string(&table)
        .map_err(|e| config_error(format!("sweep config: cannot be written as TOML: {e}")))?;
    let n = Plan::new(sweep).map_err(sweep_error)?.n_runs();
    Ok((text, n))
}

/// Runs `start..stop` of a sweep given as self-contained text ([`resolve_sweep`]), in memory,
/// on `threads` workers; the rows as an Arrow IPC stream. A pure function of its arguments, so
/// a task scheduler may run it twice.
#[pyfunction]
#[pyo3(signature = (text, start, stop, threads=None))]
pub fn sweep_runs<'py>(
    py: Python<'py>,
    text: &str,
    start: u64,
    stop: u64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyBytes>> {
    let sweep = SweepFile::from_str_at(text, Path::new("<resolved sweep>"))
        .map_err(|e| config_error(format!("sweep config: {e}")))?;
    let schema = cushion_sweep::summary_table::TableSchema::new(&sweep.axes).arrow;
    let cancel = AtomicBool::new(false);
    let counts = (AtomicU64::new(0), AtomicU64::new(0));
    let hooks = Hooks {
        cancel: Some(&cancel),
        ..Default::default()
    };
    let batches = run_detached(py, &cancel, &counts, None, || {
        let plan = Plan::new(sweep)?;
        let runs = Runs::range(plan.n_runs(), start, stop)?;
        compute(&plan, runs, threads, &hooks)
    })?;
    ipc_bytes(py, &batches, schema)
}
