//! The compute-only sweep engine: a sweep given in memory runs, in parallel, and hands back its
//! summary rows as Arrow record batches. It reads and writes no file; the file layer above it
//! (`runner.rs`: chunks on disk, resume, lock, final files) and the Python bindings both use it.
//!
//! Runs are computed in chunks of `[output] chunk_size` (default 256): the runs of a chunk are
//! spread over a rayon pool and collected in run order, so the rows do not depend on the thread
//! count (each run is one independent solve; nothing is summed across runs). Between runs the
//! engine looks at the caller's cancel flag, so a cancelled sweep stops within one chunk.

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use arrow_array::RecordBatch;
use cushion_model::{simulate, RunOptions, RunResult, Scene, Summary};
use rayon::prelude::*;
use toml::Value;

use crate::error::SweepError;
use crate::runs::Runs;
use crate::sampling::Design;
use crate::summary_table::{RowsBuilder, TableSchema};
use crate::sweep_file::{InvalidRuns, SweepFile};

/// The function that runs one scene: the real model, or a stand-in in tests.
pub type Model = dyn Fn(&Scene, &RunOptions) -> RunResult + Sync;

/// What the caller hears from a running sweep, and how it stops one. All optional.
#[derive(Clone, Copy, Default)]
pub struct Hooks<'a> {
    /// After each run: (runs done, runs in the selection). Runs finished by an earlier,
    /// resumed invocation count as done. Called from worker threads.
    pub progress: Option<&'a (dyn Fn(u64, u64) + Sync)>,
    /// Raised by the caller to stop: no new run starts, and the sweep returns
    /// [`SweepError::Cancelled`] (the file layer keeps every finished chunk).
    pub cancel: Option<&'a AtomicBool>,
    /// File layer only: after each chunk file is on disk, with the number of chunks this call
    /// has written so far.
    pub chunk_written: Option<&'a (dyn Fn(usize) + Sync)>,
}

impl Hooks<'_> {
    pub(crate) fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// Runs finished so far (across chunks, and across invocations of a resumed sweep) out of
/// the runs of the selection.
pub struct RunCount {
    pub done: AtomicU64,
    pub total: u64,
}

impl RunCount {
    pub fn new(done: u64, total: u64) -> RunCount {
        RunCount {
            done: AtomicU64::new(done),
            total,
        }
    }
}

/// One computed run: its number, its axis values and its result.
pub struct RunRow {
    pub run: u64,
    pub point: Vec<Value>,
    pub result: RunResult,
}

/// A sweep ready to run: the parsed file, its sampling design and its table's columns.
pub struct Plan {
    pub sweep: SweepFile,
    pub design: Design,
    pub schema: TableSchema,
}

/// A rayon pool of `threads` workers (default: every core), and that count.
pub fn thread_pool(threads: Option<usize>) -> Result<(rayon::ThreadPool, usize), SweepError> {
    let threads = match threads {
        Some(0) => {
            return Err(SweepError::Config(
                "threads = 0: must be at least 1 (or unset for every core)".into(),
            ))
        }
        Some(n) => n,
        None => std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Internal(format!("cannot start the thread pool: {e}")))?;
    Ok((pool, threads))
}

impl Plan {
    pub fn new(sweep: SweepFile) -> Result<Plan, SweepError> {
        let design = Design::new(&sweep).map_err(SweepError::Config)?;
        let schema = TableSchema::new(&sweep.axes);
        Ok(Plan {
            sweep,
            design,
            schema,
        })
    }

    /// Runs in the whole sweep.
    pub fn n_runs(&self) -> u64 {
        self.design.n_runs()
    }

    /// Build and check every run's scene before any run starts. A run whose scene the model
    /// rejects fails the sweep (naming the run, its axis values and the key), unless the file
    /// says `invalid_runs = "row"`; a value that cannot be set at all always fails it.
    pub fn check_scenes(&self, pool: &rayon::ThreadPool) -> Result<(), SweepError> {
        let (design, sweep) = (&self.design, &self.sweep);
        let first_bad = pool.install(|| {
            (0..self.n_runs()).into_par_iter().find_map_first(|run| {
                let point = design.point(run);
                let checked = design
                    .scene(&sweep.base, &point)
                    .and_then(|s| s.validate().map_err(|e| e.to_string()));
                checked.err().map(|e| (run, point, e))
            })
        });
        let Some((run, point, e)) = first_bad else {
            return Ok(());
        };
        let bad_set = design.scene(&sweep.base, &point).is_err();
        if bad_set || sweep.invalid_runs == InvalidRuns::Fail {
            return Err(SweepError::Config(format!(
                "{}: run {run} ({}): {e}{}",
                sweep.path.display(),
                self.describe_point(&point),
                if bad_set {
                    ""
                } else {
                    " (set [output] invalid_runs = \"row\" to record such runs as rows with status invalid)"
                }
            )));
        }
        Ok(())
    }

    fn describe_point(&self, point: &[Value]) -> String {
        self.sweep
            .axes
            .iter()
            .zip(point)
            .map(|(a, v)| format!("{} = {v}", a.key))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// One run: its scene built and checked, then solved. A scene the model rejects, or a
    /// panic in the model, is a row with status `invalid` (the sweep goes on).
    pub fn run(&self, run: u64, sim: &Model) -> RunRow {
        let point = self.design.point(run);
        let ropts = RunOptions {
            trajectory: self.sweep.record.wants(run),
            sample_interval: self.sweep.sample_interval,
        };
        let result = match self.design.scene(&self.sweep.base, &point) {
            Ok(scene) => match scene.validate() {
                Ok(()) => run_guarded(sim, &scene, &ropts),
                Err(e) => invalid(e.to_string()),
            },
            Err(e) => invalid(e),
        };
        RunRow { run, point, result }
    }

    /// The runs `runs.get(i)` for `i` in `indices`, in order, on `pool`. `count` counts
    /// finished runs across calls, for `hooks.progress`.
    pub fn compute_chunk(
        &self,
        runs: &Runs,
        indices: std::ops::Range<u64>,
        pool: &rayon::ThreadPool,
        sim: &Model,
        hooks: &Hooks,
        count: &RunCount,
    ) -> Result<Vec<RunRow>, SweepError> {
        let rows: Vec<Option<RunRow>> = pool.install(|| {
            indices
                .into_par_iter()
                .map(|i| {
                    if hooks.cancelled() {
                        return None;
                    }
                    let row = self.run(runs.get(i), sim);
                    let d = count.done.fetch_add(1, Ordering::Relaxed) + 1;
                    if let Some(p) = hooks.progress {
                        p(d, count.total);
                    }
                    Some(row)
                })
                .collect()
        });
        rows.into_iter()
            .collect::<Option<Vec<RunRow>>>()
            .ok_or(SweepError::Cancelled)
    }

    /// The summary rows of computed runs as one record batch.
    pub fn batch(&self, rows: &[RunRow]) -> RecordBatch {
        let mut b = RowsBuilder::new(&self.schema);
        for r in rows {
            b.push(r.run, &r.point, &r.result.summary);
        }
        b.finish()
    }

    /// The chunks of a selection: index ranges of `[output] chunk_size` runs.
    pub fn chunks(&self, runs: &Runs) -> impl Iterator<Item = std::ops::Range<u64>> {
        let (m, c) = (runs.len(), self.sweep.chunk_size.max(1) as u64);
        (0..m.div_ceil(c)).map(move |k| (k * c)..((k + 1) * c).min(m))
    }
}

/// Compute the selected runs of a sweep in memory and return their summary rows, one batch per
/// chunk, in run order. Every run's scene is checked first (as the file layer does). Recorded
/// trajectories are not kept: the file layer writes them.
pub fn compute(
    plan: &Plan,
    runs: Runs,
    threads: Option<usize>,
    hooks: &Hooks,
) -> Result<Vec<RecordBatch>, SweepError> {
    compute_with(plan, runs, threads, hooks, &simulate)
}

/// [`compute`] with any model function.
pub fn compute_with(
    plan: &Plan,
    runs: Runs,
    threads: Option<usize>,
    hooks: &Hooks,
    sim: &Model,
) -> Result<Vec<RecordBatch>, SweepError> {
    let (pool, _) = thread_pool(threads)?;
    plan.check_scenes(&pool)?;
    let count = RunCount::new(0, runs.len());
    let mut batches = Vec::new();
    for indices in plan.chunks(&runs) {
        if hooks.cancelled() {
            return Err(SweepError::Cancelled);
        }
        let rows = plan.compute_chunk(&runs, indices, &pool, sim, hooks, &count)?;
        batches.push(plan.batch(&rows));
    }
    if batches.is_empty() {
        batches.push(plan.batch(&[]));
    }
    Ok(batches)
}

/// Compute a list of scenes, in parallel on `pool`, for a caller that chooses its runs one batch
/// at a time (design questions): the summaries come back in the list's order, so they do not
/// depend on the thread count. As in a sweep, each scene is checked first (one the model rejects,
/// or a panic in the model, is a summary with status `invalid`), the cancel flag is looked at
/// between runs ([`SweepError::Cancelled`]: the batch is dropped whole), and `hooks.progress`
/// hears `count` after each run.
pub fn compute_scenes(
    scenes: &[Scene],
    pool: &rayon::ThreadPool,
    sim: &Model,
    hooks: &Hooks,
    count: &RunCount,
) -> Result<Vec<Summary>, SweepError> {
    let ropts = RunOptions::default();
    let summaries: Vec<Option<Summary>> = pool.install(|| {
        scenes
            .par_iter()
            .map(|scene| {
                if hooks.cancelled() {
                    return None;
                }
                let result = match scene.validate() {
                    Ok(()) => run_guarded(sim, scene, &ropts),
                    Err(e) => invalid(e.to_string()),
                };
                let d = count.done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(p) = hooks.progress {
                    p(d, count.total);
                }
                Some(result.summary)
            })
            .collect()
    });
    summaries
        .into_iter()
        .collect::<Option<Vec<Summary>>>()
        .ok_or(SweepError::Cancelled)
}

fn invalid(message: String) -> RunResult {
    RunResult {
        summary: Summary::invalid(message),
        trajectory: None,
        events: Vec::new(),
    }
}

fn run_guarded(sim: &Model, scene: &Scene, ropts: &RunOptions) -> RunResult {
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
