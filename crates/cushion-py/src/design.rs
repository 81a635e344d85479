//! Design questions from Python: `cushion.design(config)` answers a design file (or a dict of
//! its shape) through `cushion-design`, with the GIL released, and hands the answer back as a
//! `DesignAnswer` holding the result: the design points and the runs as Arrow IPC streams,
//! `answer.json`'s text, and the refined map's classification of any design point. With
//! `out`, every file `cushion design --out` writes is written there too.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use cushion_design::engine_runs::{compute_design, DesignResult};
use cushion_design::output::{run_design, DesignOptions};
use cushion_design::tables::{answer_json, design_table};
use cushion_design::DesignFile;
use cushion_sweep::Hooks;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::{file_config, to_toml};
use crate::errors::{config_error, sweep_error};
use crate::sweep::{ipc_bytes, run_detached};

/// The design question a user gave: a path to a design file, or a dict of the same shape.
fn design_from(config: &Bound<'_, PyAny>) -> PyResult<DesignFile> {
    file_config(
        config,
        "design",
        "design",
        DesignFile::from_file,
        DesignFile::from_str_at,
    )
}

/// An answered design question (see `cushion.Design`, which wraps it).
#[pyclass(name = "DesignAnswer", module = "cushion._cushion", frozen)]
pub struct DesignAnswer {
    result: DesignResult,
    out_dir: Option<PathBuf>,
}

#[pymethods]
impl DesignAnswer {
    /// One row per evaluated design point (the columns of `design.parquet`), as Arrow IPC.
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let table = design_table(&self.result);
        ipc_bytes(py, std::slice::from_ref(&table), table.schema())
    }

    /// Every run made (the columns of `runs.parquet`), as Arrow IPC.
    fn runs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let schema = match self.result.runs.first() {
            Some(b) => b.schema(),
            None => return Err(config_error("the question made no runs")),
        };
        ipc_bytes(py, &self.result.runs, schema)
    }

    /// The text of `answer.json`.
    fn answer(&self) -> String {
        answer_json(&self.result).to_string()
    }

    /// The design keys, in the file's order.
    #[getter]
    fn design_keys(&self) -> Vec<String> {
        self.result
            .file
            .design
            .iter()
            .map(|a| a.key.clone())
            .collect()
    }

    /// The output folder, when the files were written.
    #[getter]
    fn out_dir(&self) -> Option<String> {
        self.out_dir.as_ref().map(|p| p.display().to_string())
    }

    /// The refined map's margin at each design point (a list of values, one per design key):
    /// interpolated between the corners of the cell the point falls in; >= 0 is feasible.
    fn map_margin(&self, points: Vec<Vec<Bound<'_, PyAny>>>) -> PyResult<Vec<f64>> {
        let keys = self.design_keys();
        points
            .iter()
            .map(|row| {
                let values = row
                    .iter()
                    .enumerate()
                    .map(|(i, v)| to_toml(keys.get(i).map_or("design", |k| k.as_str()), v))
                    .collect::<PyResult<Vec<toml::Value>>>()?;
                self.result.map_margin(&values).map_err(sweep_error)
            })
            .collect()
    }
}

/// Answer a design question; with `out`, write every file of `cushion design` there too.
#[pyfunction]
#[pyo3(signature = (config, threads=None, out=None, progress=None, git_commit=None))]
pub fn design(
    py: Python<'_>,
    config: &Bound<'_, PyAny>,
    threads: Option<usize>,
    out: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    git_commit: Option<String>,
) -> PyResult<DesignAnswer> {
    let file = design_from(config)?;
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
    let out_dir = out.clone();
    let result = run_detached(py, &cancel, &counts, progress, || match out {
        None => compute_design(file, threads, &hooks),
        Some(dir) => {
            let opts = DesignOptions {
                out: Some(dir),
                threads,
                git_commit,
            };
            run_design(file, &opts, &hooks).map(|o| o.result)
        }
    })?;
    Ok(DesignAnswer { result, out_dir })
}
