//! The parallel sweep runner.
//!
//! A sweep of `n` runs (0-based run numbers) is cut, after sharding, into chunks of
//! `[output] chunk_size` runs (default 256). Chunks are done one after the other; the runs of a
//! chunk are spread over a rayon pool of `--threads` workers and collected in run order, so the
//! output does not depend on the thread count (each run is one independent solve; nothing is
//! summed across runs).
//!
//! On disk, in the output folder `DIR`:
//! - while running, `DIR/.sweep/` holds `state.json` (what is being run: sweep digest, run
//!   count, shard, chunk size) and one `chunk-NNNNNNNN.parquet` per finished chunk (plus
//!   `chunk-NNNNNNNN.mcap` with the chunk's recorded trajectories), each written to a temporary
//!   file, fsynced, then renamed: a chunk file that exists is complete, and it is the journal.
//!   Killed at any moment, a sweep loses at most the chunk in flight; `--resume` skips the
//!   chunks whose file exists. Each invocation also keeps its running time there
//!   (`invocations.rs`), so that `provenance.json` gives the wall time of all of them.
//! - at the end, `summary.parquet`, `summary.csv` and `trajectories.mcap` (when something is
//!   recorded) are assembled from the chunk files in run order, each written atomically
//!   (temporary file, fsync, rename); then `sweep.toml` (a copy of the sweep file),
//!   `provenance.json`, the report charts (`report-*.svg`), and `.sweep/` is removed.
//! - throughout, the empty `DIR/.sweep.lock` is locked (`out_lock.rs`): a second sweep into
//!   the same folder is refused (exit status 2) before it reads or writes anything there.
//!
//! `--shard K/N` runs the runs with `run % N == K - 1` (interleaved, so each shard gets a fair
//! share of every part of a grid); `cushion merge` joins the shards' summaries.

use std::fs;
use std::io::{IsTerminal, Write};
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use cushion_model::{simulate, RunOptions, RunResult, Scene, Summary};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use rayon::prelude::*;
use toml::Value;

use crate::atomic::{write_atomic, AtomicFile};
use crate::invocations::Invocation;
use crate::out_lock::OutputLock;
use crate::sampling::Design;
use crate::summary_table::{parquet_properties, write_csv_rows, RowsBuilder, TableSchema};
use crate::sweep_file::{InvalidRuns, SweepFile};

/// What `cushion sweep` was asked.
#[derive(Clone, Debug, Default)]
pub struct SweepOptions {
    pub file: PathBuf,
    /// Output folder (default: `runs/<sweep name>`, or `runs/<name>-shard-K-of-N` for a shard).
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    pub threads: Option<usize>,
    pub resume: bool,
    /// `(k, n)`: run the k-th of n deterministic shards (1-based k).
    pub shard: Option<(usize, usize)>,
    pub quiet: bool,
}

/// What a finished sweep did.
#[derive(Clone, Debug, Default)]
pub struct SweepOutcome {
    pub out_dir: PathBuf,
    /// Runs in the output (the shard's runs when sharded).
    pub runs_total: usize,
    /// Runs computed by this call (less than `runs_total` when resumed).
    pub runs_done_now: usize,
    /// Rows whose status is not `ok`.
    pub runs_failed: usize,
    pub wall_seconds: f64,
}

/// Why a sweep could not run. `Config` is the user's fault (exit status 2).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error("{0}")]
    Config(String),
    #[error("{0}")]
    Io(String),
}

impl SweepError {
    /// The exit status the command should use.
    pub fn exit_code(&self) -> i32 {
        match self {
            SweepError::Config(_) => 2,
            SweepError::Io(_) => 1,
        }
    }
}

/// An I/O error (exit status 1) about `what`: `"{what}: {e}"`.
pub(crate) fn io_err(what: impl std::fmt::Display, e: impl std::fmt::Display) -> SweepError {
    SweepError::Io(format!("{what}: {e}"))
}

/// Name of the working folder inside the output folder.
pub const STATE_DIR: &str = ".sweep";
/// Test hook: abort the process (exit status 99, no cleanup, like a kill) after this many
/// chunks were finished by this process.
pub const ABORT_ENV: &str = "CUSHION_SWEEP_ABORT_AFTER_CHUNKS";

/// The files a sweep writes in its output folder (and removes when starting afresh).
pub const OUTPUT_FILES: &[&str] = &[
    "summary.parquet",
    "summary.csv",
    "trajectories.mcap",
    "sweep.toml",
    "provenance.json",
    crate::report::SPEED_FORCE_SVG,
    crate::report::HEATMAP_SVG,
];

/// FNV-1a, 64 bits: a stable digest of what a sweep computes (file text and resolved scene).
pub fn digest(parts: &[&str]) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for p in parts {
        for b in p.as_bytes().iter().chain(std::iter::once(&0u8)) {
            h ^= *b as u64;
            h = h.wrapping_mul(0x100000001b3);
        }
    }
    format!("{h:016x}")
}

fn sweep_digest(sweep: &SweepFile) -> String {
    let base = toml::to_string(&sweep.base.to_toml()).unwrap_or_default();
    digest(&[&sweep.text, &base])
}

/// Run a sweep file with the real model.
pub fn run_sweep(opts: &SweepOptions) -> Result<SweepOutcome, SweepError> {
    run_sweep_with(opts, &simulate)
}

/// The run numbers of a shard: `run % n == k - 1`, ascending. `i`-th run of the shard.
fn shard_run(i: u64, shard: (usize, usize)) -> u64 {
    i * shard.1 as u64 + (shard.0 as u64 - 1)
}

fn shard_len(n_runs: u64, shard: (usize, usize)) -> u64 {
    let (k, n) = (shard.0 as u64, shard.1 as u64);
    if n_runs < k {
        0
    } else {
        (n_runs - k) / n + 1
    }
}

fn describe_point(sweep: &SweepFile, point: &[Value]) -> String {
    sweep
        .axes
        .iter()
        .zip(point)
        .map(|(a, v)| format!("{} = {v}", a.key))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Run a sweep file with any model function (tests use a fake one).
pub fn run_sweep_with(
    opts: &SweepOptions,
    sim: &(dyn Fn(&Scene, &RunOptions) -> RunResult + Sync),
) -> Result<SweepOutcome, SweepError> {
    let started = Instant::now();
    let sweep = SweepFile::from_file(&opts.file).map_err(SweepError::Config)?;
    let threads = match opts.threads {
        Some(0) => return Err(SweepError::Config("--threads must be at least 1".into())),
        Some(n) => n,
        None => std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
    };
    let shard = opts.shard.unwrap_or((1, 1));
    if shard.1 == 0 || shard.0 == 0 || shard.0 > shard.1 {
        return Err(SweepError::Config(format!(
            "--shard {}/{}: K must be from 1 to N",
            shard.0, shard.1
        )));
    }
    let design = Design::new(&sweep).map_err(SweepError::Config)?;
    let n_runs = design.n_runs();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| io_err("cannot start the thread pool", e))?;

    // Every run's scene is built and checked before any run starts.
    let timing = std::env::var_os("CUSHION_SWEEP_TIMING").is_some();
    let phase = |what: &str, since: Instant| {
        if timing {
            eprintln!(
                "cushion sweep: {what}: {:.3} s",
                since.elapsed().as_secs_f64()
            );
        }
    };
    let t_phase = Instant::now();
    let first_bad = pool.install(|| {
        (0..n_runs).into_par_iter().find_map_first(|run| {
            let point = design.point(run);
            let checked = design
                .scene(&sweep.base, &point)
                .and_then(|s| s.validate().map_err(|e| e.to_string()));
            match checked {
                Ok(()) => None,
                Err(e) => Some((run, point, e)),
            }
        })
    });
    if let Some((run, point, e)) = first_bad {
        let bad_set = first_bad_is_set_error(&design, &sweep, &point);
        if bad_set || sweep.invalid_runs == InvalidRuns::Fail {
            return Err(SweepError::Config(format!(
                "{}: run {run} ({}): {e}{}",
                opts.file.display(),
                describe_point(&sweep, &point),
                if bad_set {
                    ""
                } else {
                    " (set [output] invalid_runs = \"row\" to record such runs as rows with status invalid)"
                }
            )));
        }
    }

    phase("parse and check every run's scene", t_phase);
    let out_dir = opts.out.clone().unwrap_or_else(|| {
        let name = if shard.1 > 1 {
            format!("{}-shard-{}-of-{}", sweep.name, shard.0, shard.1)
        } else {
            sweep.name.clone()
        };
        PathBuf::from("runs").join(name)
    });
    let state_dir = out_dir.join(STATE_DIR);
    let digest = sweep_digest(&sweep);
    let state = serde_json::json!({
        "format": 1,
        "sweep_digest": digest,
        "n_runs": n_runs,
        "shard": [shard.0, shard.1],
        "chunk_size": sweep.chunk_size,
    });

    // One sweep at a time in this folder, from here until this function returns.
    let _lock = OutputLock::take_for("cushion sweep", &out_dir)?;
    if state_dir.exists() {
        let old: Option<serde_json::Value> = fs::read(state_dir.join("state.json"))
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok());
        if !opts.resume {
            let n = count_chunks(&state_dir);
            return Err(SweepError::Config(format!(
                "{} holds an unfinished sweep ({n} chunk(s) done): pass --resume to continue it, or remove the folder or choose another --out",
                out_dir.display()
            )));
        }
        if let Some(old) = &old {
            if old != &state {
                return Err(SweepError::Config(format!(
                    "--resume: {} holds a different sweep (sweep file, base scene, shard or chunk size changed): {old} vs {state}",
                    out_dir.display()
                )));
            }
        }
    } else if opts.resume && finished_same(&out_dir, &digest, shard) {
        // Nothing left to do.
        let m = shard_len(n_runs, shard) as usize;
        let failed = count_failed(&out_dir.join("summary.parquet")).unwrap_or(0);
        return Ok(SweepOutcome {
            out_dir,
            runs_total: m,
            runs_done_now: 0,
            runs_failed: failed,
            wall_seconds: started.elapsed().as_secs_f64(),
        });
    } else {
        // A fresh start: remove a previous sweep's outputs (ours only).
        for f in OUTPUT_FILES {
            let p = out_dir.join(f);
            if p.exists() {
                fs::remove_file(&p).map_err(|e| io_err(p.display(), e))?;
            }
        }
    }
    remove_stale_temps(&out_dir);
    fs::create_dir_all(&state_dir).map_err(|e| io_err(state_dir.display(), e))?;
    write_atomic(&state_dir.join("state.json"), state.to_string().as_bytes())
        .map_err(|e| io_err(state_dir.display(), e))?;
    let invocation = Invocation::new(&state_dir, started);

    let schema = TableSchema::new(&sweep.axes);
    let m = shard_len(n_runs, shard);
    let chunk = sweep.chunk_size as u64;
    let n_chunks = m.div_ceil(chunk);
    let chunk_path = |c: u64, ext: &str| state_dir.join(format!("chunk-{c:08}.{ext}"));
    let todo: Vec<u64> = (0..n_chunks)
        .filter(|c| !chunk_path(*c, "parquet").exists())
        .collect();
    let runs_in = |c: u64| (c * chunk)..((c + 1) * chunk).min(m);
    let runs_todo: u64 = todo
        .iter()
        .map(|c| runs_in(*c).end - runs_in(*c).start)
        .sum();

    let progress = if !opts.quiet && std::io::stderr().is_terminal() {
        let pb = indicatif::ProgressBar::new(m);
        pb.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs  {rate}  ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .with_key(
                "rate",
                |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.0} runs/s", s.per_sec());
                },
            ),
        );
        pb.set_position(m - runs_todo);
        pb.reset_eta();
        Some(pb)
    } else {
        None
    };
    let abort_after: Option<usize> = std::env::var(ABORT_ENV).ok().and_then(|v| v.parse().ok());
    let chunks_done_now = AtomicUsize::new(0);

    let t_phase = Instant::now();
    // Chunks are computed one after another (runs inside a chunk share the pool), and each
    // finished chunk is handed to a writer thread, so writing chunk k overlaps computing chunk
    // k + 1. The writer takes chunks in order; at most one computed chunk waits for it.
    type ChunkResults = Vec<(u64, Vec<Value>, RunResult)>;
    let (to_writer, from_runner) = std::sync::mpsc::sync_channel::<(u64, ChunkResults)>(1);
    let write_seconds = std::thread::scope(|scope| -> Result<f64, SweepError> {
        let writer = scope.spawn(|| -> Result<f64, SweepError> {
            let mut write_seconds = 0.0;
            for (c, results) in from_runner {
                let t_write = Instant::now();
                write_chunk(
                    &chunk_path(c, "mcap"),
                    &chunk_path(c, "parquet"),
                    &schema,
                    &results,
                )?;
                write_seconds += t_write.elapsed().as_secs_f64();
                // bookkeeping only: a sweep does not fail for it
                let _ = invocation.record();
                let done = chunks_done_now.fetch_add(1, Ordering::SeqCst) + 1;
                if abort_after == Some(done) {
                    eprintln!("cushion sweep: {ABORT_ENV}={done}: stopping abruptly (test hook)");
                    std::process::exit(99);
                }
            }
            Ok(write_seconds)
        });
        for c in &todo {
            let c = *c;
            let results: ChunkResults = pool.install(|| {
                runs_in(c)
                    .into_par_iter()
                    .map(|i| {
                        let run = shard_run(i, shard);
                        let point = design.point(run);
                        let ropts = RunOptions {
                            trajectory: sweep.record.wants(run),
                            sample_interval: sweep.sample_interval,
                        };
                        let result = match design.scene(&sweep.base, &point) {
                            Ok(scene) => match scene.validate() {
                                Ok(()) => run_guarded(sim, &scene, &ropts),
                                Err(e) => invalid(e.to_string()),
                            },
                            Err(e) => invalid(e),
                        };
                        if let Some(pb) = &progress {
                            pb.inc(1);
                        }
                        (run, point, result)
                    })
                    .collect()
            });
            if to_writer.send((c, results)).is_err() {
                break; // the writer failed: its error is returned below
            }
        }
        drop(to_writer);
        writer
            .join()
            .unwrap_or_else(|_| Err(SweepError::Io("the chunk writer thread panicked".into())))
    })?;
    if let Some(pb) = &progress {
        pb.finish_and_clear();
    }

    phase("runs and chunk files", t_phase);
    if timing {
        eprintln!("cushion sweep:   of which writing chunk files (serial): {write_seconds:.3} s");
    }
    let t_phase = Instant::now();
    // Assemble the final files from the chunk files, in run order.
    let failed = assemble(&out_dir, &state_dir, &schema, n_chunks, sweep.record.any())?;
    write_atomic(&out_dir.join("sweep.toml"), sweep.text.as_bytes())
        .map_err(|e| io_err(out_dir.display(), e))?;
    let wall = started.elapsed().as_secs_f64();
    let provenance = provenance(
        &sweep,
        &digest,
        n_runs,
        shard,
        m,
        failed,
        runs_todo,
        opts.resume,
        threads,
        wall,
        invocation.earlier(),
    );
    write_atomic(
        &out_dir.join("provenance.json"),
        serde_json::to_string_pretty(&provenance)
            .unwrap_or_default()
            .as_bytes(),
    )
    .map_err(|e| io_err(out_dir.display(), e))?;
    phase("final files", t_phase);
    let t_phase = Instant::now();
    if let Err(e) = crate::report::write_report(&out_dir) {
        eprintln!("cushion sweep: warning: report charts not written: {e}");
    }
    phase("report", t_phase);
    fs::remove_dir_all(&state_dir).map_err(|e| io_err(state_dir.display(), e))?;

    Ok(SweepOutcome {
        out_dir,
        runs_total: m as usize,
        runs_done_now: runs_todo as usize,
        runs_failed: failed,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

/// Whether the first bad run is bad because a value cannot be set at all (wrong type, unknown
/// value), which is always a sweep-file error.
fn first_bad_is_set_error(design: &Design, sweep: &SweepFile, point: &[Value]) -> bool {
    design.scene(&sweep.base, point).is_err()
}

/// Write one finished chunk: its recorded trajectories (if any) to `mcap_path`, then its rows
/// to `parquet_path`. The Parquet file is written last: its presence marks the chunk done.
fn write_chunk(
    mcap_path: &Path,
    parquet_path: &Path,
    schema: &TableSchema,
    results: &[(u64, Vec<Value>, RunResult)],
) -> Result<(), SweepError> {
    let recorded: Vec<&(u64, Vec<Value>, RunResult)> = results
        .iter()
        .filter(|r| r.2.trajectory.is_some())
        .collect();
    if !recorded.is_empty() {
        let path = mcap_path;
        let mut f = AtomicFile::create(path).map_err(|e| io_err(path.display(), e))?;
        {
            let mut w = crate::trajectory_mcap::write_options()
                .create(f.writer())
                .map_err(|e| io_err(path.display(), e))?;
            for (run, _, r) in &recorded {
                if let Some(traj) = r.trajectory.as_ref() {
                    crate::trajectory_mcap::write_run(
                        &mut w,
                        &format!("/run/{run}"),
                        traj,
                        &r.events,
                    )
                    .map_err(|e| io_err(path.display(), e))?;
                }
            }
            w.finish().map_err(|e| io_err(path.display(), e))?;
        }
        f.commit().map_err(|e| io_err(path.display(), e))?;
    }
    let mut rows = RowsBuilder::new(schema);
    for (run, point, r) in results {
        rows.push(*run, point, &r.summary);
    }
    let batch = rows.finish();
    write_parquet_atomic(parquet_path, schema, std::iter::once(Ok(batch)))
}

fn invalid(message: String) -> RunResult {
    RunResult {
        summary: Summary::invalid(message),
        trajectory: None,
        events: Vec::new(),
    }
}

/// One run; a panic in the model becomes a row with status `invalid` (the sweep goes on).
fn run_guarded(
    sim: &(dyn Fn(&Scene, &RunOptions) -> RunResult + Sync),
    scene: &Scene,
    ropts: &RunOptions,
) -> RunResult {
    match std::panic::catch_unwind(AssertUnwindSafe(|| sim(scene, ropts))) {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".to_string());
            invalid(format!("internal error: the model panicked: {msg}"))
        }
    }
}

/// Temporary files of our outputs left by a process killed while writing them.
fn remove_stale_temps(out_dir: &Path) {
    let Ok(entries) = fs::read_dir(out_dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if OUTPUT_FILES
            .iter()
            .any(|f| name.starts_with(&format!(".{f}.tmp-")))
        {
            let _ = fs::remove_file(e.path());
        }
    }
}

fn count_chunks(state_dir: &Path) -> usize {
    fs::read_dir(state_dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .filter(|e| {
                    let n = e.file_name().to_string_lossy().into_owned();
                    n.starts_with("chunk-") && n.ends_with(".parquet")
                })
                .count()
        })
        .unwrap_or(0)
}

/// A finished sweep of the same digest and shard is in `out_dir`.
fn finished_same(out_dir: &Path, digest: &str, shard: (usize, usize)) -> bool {
    let Ok(bytes) = fs::read(out_dir.join("provenance.json")) else {
        return false;
    };
    let Ok(p) = serde_json::from_slice::<serde_json::Value>(&bytes) else {
        return false;
    };
    out_dir.join("summary.parquet").exists()
        && p["sweep_digest"] == digest
        && p["shard"]["k"] == shard.0
        && p["shard"]["n"] == shard.1
}

/// Write record batches to a Parquet file atomically.
pub fn write_parquet_atomic(
    path: &Path,
    schema: &TableSchema,
    batches: impl Iterator<Item = Result<arrow_array::RecordBatch, SweepError>>,
) -> Result<(), SweepError> {
    let mut f = AtomicFile::create(path).map_err(|e| io_err(path.display(), e))?;
    let w = f.take();
    let mut writer = ArrowWriter::try_new(w, schema.arrow.clone(), Some(parquet_properties()))
        .map_err(|e| io_err(path.display(), e))?;
    for b in batches {
        writer.write(&b?).map_err(|e| io_err(path.display(), e))?;
    }
    let w = writer.into_inner().map_err(|e| io_err(path.display(), e))?;
    f.commit_with(w).map_err(|e| io_err(path.display(), e))
}

/// Read a Parquet file's batches one after the other.
pub fn read_parquet(
    path: &Path,
) -> Result<impl Iterator<Item = Result<arrow_array::RecordBatch, SweepError>>, SweepError> {
    let file = fs::File::open(path).map_err(|e| io_err(path.display(), e))?;
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.with_batch_size(4096).build())
        .map_err(|e| io_err(path.display(), e))?;
    let p = path.display().to_string();
    Ok(reader.map(move |b| b.map_err(|e| io_err(&p, e))))
}

pub fn count_failed_batch(batch: &arrow_array::RecordBatch) -> usize {
    let Some(col) = batch.column_by_name("status") else {
        return 0;
    };
    let Some(a) = col.as_any().downcast_ref::<arrow_array::StringArray>() else {
        return 0;
    };
    a.iter().filter(|s| *s != Some("ok")).count()
}

fn count_failed(path: &Path) -> Result<usize, SweepError> {
    let mut n = 0;
    for b in read_parquet(path)? {
        n += count_failed_batch(&b?);
    }
    Ok(n)
}

/// Build `summary.parquet`, `summary.csv` (and `trajectories.mcap`) from the chunk files.
/// Returns the number of failed rows.
fn assemble(
    out_dir: &Path,
    state_dir: &Path,
    schema: &TableSchema,
    n_chunks: u64,
    recorded: bool,
) -> Result<usize, SweepError> {
    let chunk_path = |c: u64, ext: &str| state_dir.join(format!("chunk-{c:08}.{ext}"));
    let batches = || {
        (0..n_chunks).flat_map(move |c| match read_parquet(&chunk_path(c, "parquet")) {
            Ok(it) => Box::new(it) as Box<dyn Iterator<Item = _>>,
            Err(e) => Box::new(std::iter::once(Err(e))),
        })
    };
    // The CSV (text formatting) on a second thread while this one writes the Parquet file.
    let csv_path = out_dir.join("summary.csv");
    let write_csv = || -> Result<(usize, AtomicFile), SweepError> {
        let mut csv = AtomicFile::create(&csv_path).map_err(|e| io_err(csv_path.display(), e))?;
        writeln!(csv.writer(), "{}", schema.csv_header())
            .map_err(|e| io_err(csv_path.display(), e))?;
        let mut failed = 0usize;
        for b in batches() {
            let b = b?;
            failed += count_failed_batch(&b);
            write_csv_rows(csv.writer(), &b).map_err(|e| io_err(csv_path.display(), e))?;
        }
        Ok((failed, csv))
    };
    let (pq, csv) = std::thread::scope(|sc| {
        let h = sc.spawn(write_csv);
        let pq = write_parquet_atomic(&out_dir.join("summary.parquet"), schema, batches());
        (pq, h.join())
    });
    pq?;
    let (failed, csv) =
        csv.map_err(|_| SweepError::Io("summary.csv: writer thread panicked".into()))??;
    csv.commit().map_err(|e| io_err(csv_path.display(), e))?;

    // Only when a run of this output was recorded (a shard may hold none of the listed runs).
    if recorded && (0..n_chunks).any(|c| chunk_path(c, "mcap").exists()) {
        let path = out_dir.join("trajectories.mcap");
        let mut f = AtomicFile::create(&path).map_err(|e| io_err(path.display(), e))?;
        {
            let mut w = crate::trajectory_mcap::write_options()
                .create(f.writer())
                .map_err(|e| io_err(path.display(), e))?;
            let mut channels = crate::merge::ChannelMap::default();
            for c in 0..n_chunks {
                let p = chunk_path(c, "mcap");
                if !p.exists() {
                    continue;
                }
                let bytes = fs::read(&p).map_err(|e| io_err(p.display(), e))?;
                let stream =
                    mcap::MessageStream::new(&bytes).map_err(|e| io_err(p.display(), e))?;
                for m in stream {
                    let m = m.map_err(|e| io_err(p.display(), e))?;
                    channels
                        .copy(&mut w, &m)
                        .map_err(|e| io_err(path.display(), e))?;
                }
            }
            w.finish().map_err(|e| io_err(path.display(), e))?;
        }
        f.commit().map_err(|e| io_err(path.display(), e))?;
    }
    Ok(failed)
}

/// The git commit of the working folder, when there is one.
pub fn git_commit() -> Option<String> {
    let out = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .stderr(std::process::Stdio::null())
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn unix_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

#[allow(clippy::too_many_arguments)]
fn provenance(
    sweep: &SweepFile,
    digest: &str,
    n_runs: u64,
    shard: (usize, usize),
    runs_in_output: u64,
    failed: usize,
    runs_now: u64,
    resumed: bool,
    threads: usize,
    wall: f64,
    earlier: (f64, usize),
) -> serde_json::Value {
    let get = |k: &str| {
        sweep
            .base
            .get(k)
            .ok()
            .and_then(|v| serde_json::to_value(v).ok())
            .unwrap_or(serde_json::Value::Null)
    };
    let solver: serde_json::Map<String, serde_json::Value> = Scene::keys()
        .iter()
        .filter(|k| k.starts_with("solver."))
        .map(|k| (k.to_string(), get(k)))
        .collect();
    serde_json::json!({
        "cushion_version": env!("CARGO_PKG_VERSION"),
        "git_commit": git_commit(),
        "sweep_file": sweep.path.display().to_string(),
        "sweep_name": sweep.name,
        "sweep_digest": digest,
        "mode": sweep.mode.name(),
        "samples": sweep.samples,
        "seed": sweep.seed,
        "axes": sweep.axes.iter().map(|a| a.key.clone()).collect::<Vec<_>>(),
        "n_runs_total": n_runs,
        "shard": { "k": shard.0, "n": shard.1 },
        "runs_in_output": runs_in_output,
        "runs_failed": failed,
        "runs_computed_now": runs_now,
        "resumed": resumed,
        "threads": threads,
        "chunk_size": sweep.chunk_size,
        "wall_seconds": wall,
        "wall_seconds_all_invocations": earlier.0 + wall,
        "invocations": earlier.1 + 1,
        "finished_unix_time": unix_now(),
        "solver": solver,
        "base_scene": serde_json::to_value(sweep.base.to_toml()).unwrap_or(serde_json::Value::Null),
    })
}
