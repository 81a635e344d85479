//! The output folder of a design question, `runs/<name>/` (or the caller's), like a sweep's.
//!
//! - `design.parquet` and `design.csv`: one row per evaluated design point (`tables.rs`);
//! - `runs.parquet`: every run made, with the columns of a sweep's summary and `stage`
//!   (`search` or `verify`), the design keys and the `for_all` keys as its axis columns;
//! - `answer.json`: the chosen design, its worst cases and witnesses, its margin, the
//!   verification, the runs and the wall time;
//! - `design.toml` (the design file's text), `provenance.json`, `design-map.svg`.
//!
//! The folder is locked (`.sweep.lock`, shared with sweeps and merges) from before the first
//! run until the last file is written, so two questions or a sweep cannot write into it at
//! once. Nothing is written before the answer is computed: a cancelled or failed question
//! leaves the folder as it was. Then the previous outputs are removed and each file is written
//! atomically (temporary file, fsync, rename), `provenance.json` last.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use arrow_array::RecordBatch;
use arrow_schema::DataType;
use cushion_model::simulate;
use cushion_sweep::atomic::{remove_stale_temps, write_atomic, AtomicFile};
use cushion_sweep::engine::{Hooks, Model};
use cushion_sweep::out_lock::{OutputLock, LOCK_FILE};
use cushion_sweep::parquet_io::{count_failed_batch, write_parquet_atomic};
use cushion_sweep::provenance::{base_scene, digest, solver_settings, unix_now};
use cushion_sweep::summary_table::{csv_text, write_csv_rows, ColType, TableSchema};
use cushion_sweep::SweepError;

use crate::design_file::DesignFile;
use crate::engine_runs::{compute_design_with, runs_axes, DesignResult};
use crate::tables::{answer_json, design_table};

pub const DESIGN_PARQUET: &str = "design.parquet";
pub const DESIGN_CSV: &str = "design.csv";
pub const RUNS_PARQUET: &str = "runs.parquet";
pub const ANSWER_JSON: &str = "answer.json";
pub const DESIGN_TOML: &str = "design.toml";
pub const PROVENANCE_JSON: &str = "provenance.json";
pub const DESIGN_MAP_SVG: &str = "design-map.svg";

/// The files a design question writes in its output folder (and removes before writing anew).
pub const OUTPUT_FILES: &[&str] = &[
    DESIGN_PARQUET,
    DESIGN_CSV,
    RUNS_PARQUET,
    ANSWER_JSON,
    DESIGN_TOML,
    PROVENANCE_JSON,
    DESIGN_MAP_SVG,
];

/// How to answer a design question into a folder.
#[derive(Clone, Debug, Default)]
pub struct DesignOptions {
    /// Output folder (default: `runs/<name>`).
    pub out: Option<PathBuf>,
    /// Worker threads (default: every core). The answer does not depend on it.
    pub threads: Option<usize>,
    /// The git commit of the code, for `provenance.json` (the caller finds it).
    pub git_commit: Option<String>,
}

/// A design question answered into its folder.
pub struct DesignOutcome {
    pub out_dir: PathBuf,
    pub result: DesignResult,
    /// Things the caller should tell the user (a folder that cannot be locked, a chart that
    /// could not be drawn); the question itself was answered.
    pub warnings: Vec<String>,
    /// Wall time of the whole call, files included.
    pub wall_seconds: f64,
}

/// Answer a design question with the real model and write its output folder.
pub fn run_design(
    file: DesignFile,
    opts: &DesignOptions,
    hooks: &Hooks,
) -> Result<DesignOutcome, SweepError> {
    run_design_with(file, opts, hooks, &simulate)
}

/// [`run_design`] with any model function.
pub fn run_design_with(
    file: DesignFile,
    opts: &DesignOptions,
    hooks: &Hooks,
    sim: &Model,
) -> Result<DesignOutcome, SweepError> {
    let started = std::time::Instant::now();
    if opts.threads == Some(0) {
        return Err(SweepError::Config(
            "threads = 0: must be at least 1 (or unset for every core)".into(),
        ));
    }
    let out_dir = opts
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&file.name));
    let existed = out_dir.exists();
    let lock = OutputLock::take(&out_dir).map_err(|e| e.into_sweep_error(&out_dir))?;
    let mut warnings: Vec<String> = lock.warning(&out_dir).into_iter().collect();
    remove_stale_temps(&out_dir, OUTPUT_FILES);
    let result = match compute_design_with(file, opts.threads, hooks, sim) {
        Ok(result) => result,
        Err(e) => {
            // Stopped or failed before any file: a folder this call made goes again.
            drop(lock);
            if !existed {
                let _ = fs::remove_file(out_dir.join(LOCK_FILE));
                let _ = fs::remove_dir(&out_dir);
            }
            return Err(e);
        }
    };
    warnings.extend(write_design(&result, &out_dir, opts.git_commit.as_deref())?);
    drop(lock);
    Ok(DesignOutcome {
        out_dir,
        result,
        warnings,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

fn io(what: &Path, e: impl std::fmt::Display) -> SweepError {
    SweepError::Io(format!("{}: {e}", what.display()))
}

/// Write the files of an answered question into `out_dir` (which the caller has locked, see
/// [`OutputLock`]); returns warnings (a chart that could not be drawn).
pub fn write_design(
    r: &DesignResult,
    out_dir: &Path,
    git_commit: Option<&str>,
) -> Result<Vec<String>, SweepError> {
    fs::create_dir_all(out_dir).map_err(|e| io(out_dir, e))?;
    for f in OUTPUT_FILES {
        let p = out_dir.join(f);
        if p.exists() {
            fs::remove_file(&p).map_err(|e| io(&p, e))?;
        }
    }
    let points = design_table(r);
    let path = out_dir.join(DESIGN_PARQUET);
    write_parquet_atomic(
        &path,
        &schema_of(&points),
        std::iter::once(Ok(points.clone())),
    )?;
    write_csv(&out_dir.join(DESIGN_CSV), &points)?;

    let runs_schema = TableSchema::new(&runs_axes(&r.file));
    write_parquet_atomic(
        &out_dir.join(RUNS_PARQUET),
        &runs_schema,
        r.runs.iter().cloned().map(Ok),
    )?;
    let json = |v: &serde_json::Value| serde_json::to_string_pretty(v).unwrap_or_default() + "\n";
    let path = out_dir.join(ANSWER_JSON);
    write_atomic(&path, json(&answer_json(r)).as_bytes()).map_err(|e| io(&path, e))?;
    let path = out_dir.join(DESIGN_TOML);
    write_atomic(&path, r.file.text.as_bytes()).map_err(|e| io(&path, e))?;

    let mut warnings = Vec::new();
    if let Err(e) = crate::design_map::write_design_map(&out_dir.join(DESIGN_MAP_SVG), r) {
        warnings.push(format!("{DESIGN_MAP_SVG} not written: {e}"));
    }
    let path = out_dir.join(PROVENANCE_JSON);
    write_atomic(&path, json(&provenance(r, git_commit)).as_bytes()).map_err(|e| io(&path, e))?;
    Ok(warnings)
}

/// A table schema for a batch of any columns (the Parquet writer reads its Arrow schema).
fn schema_of(b: &RecordBatch) -> TableSchema {
    let columns = b
        .schema()
        .fields()
        .iter()
        .map(|f| {
            let t = match f.data_type() {
                DataType::Int64 => ColType::Int,
                DataType::Boolean => ColType::Bool,
                DataType::Utf8 => ColType::Text,
                _ => ColType::Float,
            };
            (f.name().clone(), t)
        })
        .collect();
    TableSchema {
        columns,
        arrow: b.schema(),
        n_axes: 0,
    }
}

/// A batch as CSV, written atomically (the sweep's CSV conventions: `summary_table.rs`).
pub fn write_csv(path: &Path, b: &RecordBatch) -> Result<(), SweepError> {
    let mut f = AtomicFile::create(path).map_err(|e| io(path, e))?;
    let header: Vec<String> = b
        .schema()
        .fields()
        .iter()
        .map(|f| csv_text(f.name()))
        .collect();
    let w = f.writer();
    writeln!(w, "{}", header.join(",")).map_err(|e| io(path, e))?;
    write_csv_rows(w, b).map_err(|e| io(path, e))?;
    f.commit().map_err(|e| io(path, e))
}

/// The digest of a design question: its text and its base scene with `[set]` applied.
pub fn design_digest(file: &DesignFile) -> String {
    let base = toml::to_string(&file.base.to_toml()).unwrap_or_default();
    digest(&[&file.text, &base])
}

/// `provenance.json`: what the folder holds and how it was made.
pub fn provenance(r: &DesignResult, git_commit: Option<&str>) -> serde_json::Value {
    let file = &r.file;
    let failed: usize = r.runs.iter().map(count_failed_batch).sum();
    serde_json::json!({
        "cushion_version": env!("CARGO_PKG_VERSION"),
        "git_commit": git_commit,
        "design_file": file.path.display().to_string(),
        "design_name": file.name,
        "design_digest": design_digest(file),
        "design": file.design.iter().map(|a| a.key.clone()).collect::<Vec<_>>(),
        "for_all": file.for_all.iter().map(|a| a.key.clone()).collect::<Vec<_>>(),
        "limits": file.limits.iter().map(|l| serde_json::json!({
            "metric": l.metric, "max": l.max, "min": l.min, "abs": l.abs
        })).collect::<Vec<_>>(),
        "search": {
            "resolution": file.search.resolution,
            "tolerance": file.search.tolerance,
            "verify": file.search.verify,
        },
        "design_points": r.map.points().len(),
        "runs_total": r.search_runs + r.verify_runs,
        "runs_search": r.search_runs,
        "runs_verify": r.verify_runs,
        "runs_failed": failed,
        "batches": r.batches,
        "threads": r.threads,
        "wall_seconds": r.wall_seconds,
        "finished_unix_time": unix_now(),
        "solver": solver_settings(&file.base),
        "base_scene": base_scene(&file.base),
    })
}
