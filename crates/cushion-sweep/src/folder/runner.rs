//! The file layer of a sweep: the output folder, its lock, the journal of finished chunks,
//! resuming, and the final files. The runs themselves are computed by the engine
//! (`engine.rs`); the command line and the Python bindings both call [`run_sweep`].
//!
//! On disk, in the output folder `DIR`:
//! - while running, `DIR/.sweep/` is the journal (`journal.rs`): one file per finished chunk.
//!   Stopped at any moment (killed, cancelled, out of disk), a sweep loses at most the chunk in
//!   flight; `resume` skips the chunks that read back whole. Each invocation also keeps its
//!   running time there (`invocations.rs`), so that `provenance.json` gives the wall time of
//!   all of them.
//! - at the end, `summary.parquet`, `summary.csv` and `trajectories.mcap` (when something is
//!   recorded) are assembled from the chunk files in run order, each written atomically; then
//!   `sweep.toml` (the sweep file's text), `provenance.json`, the report charts
//!   (`report-*.svg`), and `.sweep/` is removed.
//! - throughout, the empty `DIR/.sweep.lock` is locked (`out_lock.rs`): a second sweep into
//!   the same folder is refused before it reads or writes anything there.
//!
//! Shards (`run % N == K - 1`, `runs.rs`) write their own folders; `merge.rs` joins them.

use std::fs;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::mpsc::Receiver;
use std::time::Instant;

use cushion_model::simulate;

use crate::atomic::{remove_stale_temps, write_atomic};
use crate::engine::{thread_pool, Hooks, Model, Plan, RunCount, RunRow};
use crate::error::{io_err, SweepError};
use crate::invocations::Invocation;
use crate::journal::Journal;
use crate::out_lock::OutputLock;
use crate::parquet_io::count_failed;
use crate::provenance::{finished_same, sweep_digest, Record};
use crate::runs::Runs;
use crate::sweep_file::SweepFile;

/// How to run a sweep into a folder (the sweep itself is given apart, parsed).
#[derive(Clone, Debug, Default)]
pub struct SweepOptions {
    /// Output folder (default: `runs/<sweep name>`, or `runs/<name>-shard-K-of-N` for a shard).
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    pub threads: Option<usize>,
    /// Continue an unfinished sweep in `out` (an error without it).
    pub resume: bool,
    /// `(k, n)`: run the k-th of n deterministic shards (1-based k).
    pub shard: Option<(usize, usize)>,
    /// The git commit of the code, for `provenance.json` (the caller finds it: this library
    /// spawns no program).
    pub git_commit: Option<String>,
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
    /// Things the caller should tell the user (a folder that cannot be locked, a damaged chunk
    /// that was computed again, charts that could not be drawn); the sweep itself succeeded.
    pub warnings: Vec<String>,
    /// Seconds spent in each phase, in order (checking scenes, runs and chunk files, of which
    /// writing chunk files, final files, report charts).
    pub phases: Vec<(&'static str, f64)>,
}

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

/// Run a sweep with the real model into its output folder.
pub fn run_sweep(
    sweep: SweepFile,
    opts: &SweepOptions,
    hooks: &Hooks,
) -> Result<SweepOutcome, SweepError> {
    run_sweep_with(sweep, opts, hooks, &simulate)
}

/// [`run_sweep`] with any model function (tests use a stand-in).
pub fn run_sweep_with(
    sweep: SweepFile,
    opts: &SweepOptions,
    hooks: &Hooks,
    sim: &Model,
) -> Result<SweepOutcome, SweepError> {
    let started = Instant::now();
    let mut phases = Vec::new();
    let (pool, threads) = thread_pool(opts.threads)?;
    let shard = opts.shard.unwrap_or((1, 1));
    let plan = Plan::new(sweep)?;
    let runs = Runs::shard(plan.n_runs(), shard.0, shard.1)?;

    // Every run's scene is built and checked before any run starts.
    let t_phase = Instant::now();
    plan.check_scenes(&pool)?;
    phases.push((
        "parse and check every run's scene",
        t_phase.elapsed().as_secs_f64(),
    ));

    let folder = FolderSweep::new(plan, opts, shard, runs, threads, started);
    // One sweep at a time in this folder, from here until this function returns.
    let lock =
        OutputLock::take(&folder.out_dir).map_err(|e| e.into_sweep_error(&folder.out_dir))?;
    let mut warnings: Vec<String> = lock.warning(&folder.out_dir).into_iter().collect();
    if folder.prepare()? == Start::AlreadyFinished {
        return Ok(folder.already_finished(warnings, phases));
    }
    let invocation = folder.open_journal()?;
    let chunks = folder.chunks_to_compute(&mut warnings);
    let count = RunCount::new(folder.runs.len() - chunks.runs, folder.runs.len());
    if let Some(p) = hooks.progress {
        p(count.done.load(Ordering::Relaxed), count.total);
    }

    let t_phase = Instant::now();
    let write_seconds =
        folder.compute_and_write(&chunks, &pool, sim, hooks, &count, &invocation)?;
    phases.push(("runs and chunk files", t_phase.elapsed().as_secs_f64()));
    phases.push(("  of which writing chunk files (serial)", write_seconds));

    let t_phase = Instant::now();
    let failed = folder.write_final_files(&chunks, &invocation)?;
    phases.push(("final files", t_phase.elapsed().as_secs_f64()));
    let t_phase = Instant::now();
    if let Err(e) = crate::report::write_report(&folder.out_dir) {
        warnings.push(format!("report charts not written: {e}"));
    }
    phases.push(("report", t_phase.elapsed().as_secs_f64()));
    fs::remove_dir_all(&folder.journal.dir).map_err(|e| io_err(folder.journal.dir.display(), e))?;
    drop(lock);

    Ok(SweepOutcome {
        out_dir: folder.out_dir,
        runs_total: folder.runs.len() as usize,
        runs_done_now: chunks.runs as usize,
        runs_failed: failed,
        wall_seconds: started.elapsed().as_secs_f64(),
        warnings,
        phases,
    })
}

/// A sweep this call runs into its output folder: what its phases share.
struct FolderSweep<'a> {
    plan: Plan,
    opts: &'a SweepOptions,
    /// `(k, n)`, `(1, 1)` when not sharded.
    shard: (usize, usize),
    /// Runs of the whole sweep.
    n_runs: u64,
    /// Runs of this shard.
    runs: Runs,
    threads: usize,
    started: Instant,
    out_dir: PathBuf,
    journal: Journal,
    /// Of the sweep file and base scene.
    digest: String,
    /// What the journal records of the sweep, so that a resume continues only the same one.
    state: serde_json::Value,
}

/// What [`FolderSweep::prepare`] found.
#[derive(PartialEq)]
enum Start {
    /// Nothing there, or a previous sweep's outputs, now removed.
    Fresh,
    /// An unfinished run of the same sweep, to resume.
    Unfinished,
    /// The same sweep, finished: nothing left to do.
    AlreadyFinished,
}

/// The chunks of this call's runs, and which of them still need computing.
struct ChunkList {
    ranges: Vec<std::ops::Range<u64>>,
    /// The chunks the journal does not hold whole, in order.
    todo: Vec<u64>,
    /// Runs in those chunks.
    runs: u64,
}

impl<'a> FolderSweep<'a> {
    /// The output folder is `opts.out`, by default `runs/<sweep name>` (for a shard
    /// `runs/<sweep name>-shard-K-of-N`).
    fn new(
        plan: Plan,
        opts: &'a SweepOptions,
        shard: (usize, usize),
        runs: Runs,
        threads: usize,
        started: Instant,
    ) -> FolderSweep<'a> {
        let sweep = &plan.sweep;
        let n_runs = plan.n_runs();
        let out_dir = opts.out.clone().unwrap_or_else(|| {
            let name = if shard.1 > 1 {
                format!("{}-shard-{}-of-{}", sweep.name, shard.0, shard.1)
            } else {
                sweep.name.clone()
            };
            PathBuf::from("runs").join(name)
        });
        let journal = Journal::new(&out_dir);
        let digest = sweep_digest(sweep);
        let state = serde_json::json!({
            "format": 1,
            "sweep_digest": digest,
            "n_runs": n_runs,
            "shard": [shard.0, shard.1],
            "chunk_size": sweep.chunk_size,
        });
        FolderSweep {
            plan,
            opts,
            shard,
            n_runs,
            runs,
            threads,
            started,
            out_dir,
            journal,
            digest,
            state,
        }
    }

    /// Make the folder ready: an unfinished sweep there is continued (only with `resume`, and
    /// only the same sweep), the same sweep finished there ends the call (with `resume`), and
    /// otherwise a previous sweep's outputs are removed for a fresh start.
    fn prepare(&self) -> Result<Start, SweepError> {
        let (out_dir, journal, state) = (&self.out_dir, &self.journal, &self.state);
        if journal.exists() {
            if !self.opts.resume {
                return Err(SweepError::Config(format!(
                    "{} holds an unfinished sweep ({} chunk(s) done): resume it (--resume, or resume=True), or remove the folder or choose another output folder",
                    out_dir.display(),
                    journal.count_chunks()
                )));
            }
            if let Some(old) = journal.read_state() {
                if old != *state {
                    return Err(SweepError::Config(format!(
                        "resume: {} holds a different sweep (sweep file, base scene, shard or chunk size changed): {old} vs {state}",
                        out_dir.display()
                    )));
                }
            }
            Ok(Start::Unfinished)
        } else if self.opts.resume && finished_same(out_dir, &self.digest, self.shard) {
            Ok(Start::AlreadyFinished)
        } else {
            // A fresh start: remove a previous sweep's outputs (ours only).
            for f in OUTPUT_FILES {
                let p = out_dir.join(f);
                if p.exists() {
                    fs::remove_file(&p).map_err(|e| io_err(p.display(), e))?;
                }
            }
            Ok(Start::Fresh)
        }
    }

    /// The outcome of a call that finds the same sweep finished: nothing computed now.
    fn already_finished(
        self,
        warnings: Vec<String>,
        phases: Vec<(&'static str, f64)>,
    ) -> SweepOutcome {
        let failed = count_failed(&self.out_dir.join("summary.parquet")).unwrap_or(0);
        SweepOutcome {
            out_dir: self.out_dir,
            runs_total: self.runs.len() as usize,
            runs_failed: failed,
            wall_seconds: self.started.elapsed().as_secs_f64(),
            warnings,
            phases,
            ..Default::default()
        }
    }

    /// The journal, with the sweep's state written in it, and this call's entry among the
    /// invocations.
    fn open_journal(&self) -> Result<Invocation, SweepError> {
        let journal = &self.journal;
        remove_stale_temps(&self.out_dir, OUTPUT_FILES);
        fs::create_dir_all(&journal.dir).map_err(|e| io_err(journal.dir.display(), e))?;
        write_atomic(&journal.state_path(), self.state.to_string().as_bytes())
            .map_err(|e| io_err(journal.dir.display(), e))?;
        Ok(Invocation::new(&journal.dir, self.started))
    }

    /// The chunks of the runs; those the journal holds whole (from an earlier call) are done.
    fn chunks_to_compute(&self, warnings: &mut Vec<String>) -> ChunkList {
        let ranges: Vec<std::ops::Range<u64>> = self.plan.chunks(&self.runs).collect();
        let mut todo = Vec::new();
        for (c, indices) in ranges.iter().enumerate() {
            let (done, warning) =
                self.journal
                    .check_chunk(c as u64, indices.end - indices.start, &self.plan.schema);
            warnings.extend(warning);
            if !done {
                todo.push(c as u64);
            }
        }
        let runs = todo
            .iter()
            .map(|&c| ranges[c as usize].end - ranges[c as usize].start)
            .sum();
        ChunkList { ranges, todo, runs }
    }

    /// Compute the chunks still to do and write each into the journal; the seconds spent
    /// writing.
    fn compute_and_write(
        &self,
        chunks: &ChunkList,
        pool: &rayon::ThreadPool,
        sim: &Model,
        hooks: &Hooks,
        count: &RunCount,
        invocation: &Invocation,
    ) -> Result<f64, SweepError> {
        // Chunks are computed one after another (runs inside a chunk share the pool), and each
        // finished chunk is handed to a writer thread, so writing chunk k overlaps computing
        // chunk k + 1. The writer takes chunks in order; at most one computed chunk waits for it.
        let (to_writer, from_runner) = std::sync::mpsc::sync_channel::<(u64, Vec<RunRow>)>(1);
        std::thread::scope(|scope| -> Result<f64, SweepError> {
            let writer = scope.spawn(|| self.write_chunks(from_runner, invocation, hooks));
            let mut computed = Ok(());
            for &c in &chunks.todo {
                let range = chunks.ranges[c as usize].clone();
                match self
                    .plan
                    .compute_chunk(&self.runs, range, pool, sim, hooks, count)
                {
                    Ok(rows) => {
                        if to_writer.send((c, rows)).is_err() {
                            break; // the writer failed: its error is returned below
                        }
                    }
                    Err(e) => {
                        computed = Err(e);
                        break;
                    }
                }
            }
            drop(to_writer);
            // The writer finishes the chunks already handed to it, even when cancelled.
            let written = writer.join().unwrap_or_else(|_| {
                Err(SweepError::Internal(
                    "the chunk writer thread panicked".into(),
                ))
            });
            computed.and(written)
        })
    }

    /// The writer thread: each computed chunk into the journal, in the order received; the
    /// seconds spent writing.
    fn write_chunks(
        &self,
        from_runner: Receiver<(u64, Vec<RunRow>)>,
        invocation: &Invocation,
        hooks: &Hooks,
    ) -> Result<f64, SweepError> {
        let plan = &self.plan;
        let mut write_seconds = 0.0;
        let mut chunks_written = 0;
        for (c, rows) in from_runner {
            let t_write = Instant::now();
            self.journal
                .write_chunk(c, &plan.schema, plan.batch(&rows), &rows)?;
            write_seconds += t_write.elapsed().as_secs_f64();
            // bookkeeping only: a sweep does not fail for it
            let _ = invocation.record();
            chunks_written += 1;
            if let Some(f) = hooks.chunk_written {
                f(chunks_written);
            }
        }
        Ok(write_seconds)
    }

    /// The final files: the summaries and trajectories assembled from the journal's chunks,
    /// `sweep.toml` and `provenance.json`; the number of runs not `ok`.
    fn write_final_files(
        &self,
        chunks: &ChunkList,
        invocation: &Invocation,
    ) -> Result<usize, SweepError> {
        let (sweep, out_dir) = (&self.plan.sweep, &self.out_dir);
        let n_chunks = chunks.ranges.len() as u64;
        let failed =
            self.journal
                .assemble(out_dir, &self.plan.schema, n_chunks, sweep.record.any())?;
        write_atomic(&out_dir.join("sweep.toml"), sweep.text.as_bytes())
            .map_err(|e| io_err(out_dir.display(), e))?;
        let record = Record {
            sweep,
            digest: &self.digest,
            git_commit: self.opts.git_commit.as_deref(),
            n_runs: self.n_runs,
            shard: self.shard,
            runs_in_output: self.runs.len(),
            failed,
            runs_now: chunks.runs,
            resumed: self.opts.resume,
            threads: self.threads,
            wall: self.started.elapsed().as_secs_f64(),
            earlier: invocation.earlier(),
        };
        write_atomic(
            &out_dir.join("provenance.json"),
            serde_json::to_string_pretty(&record.to_json())
                .unwrap_or_default()
                .as_bytes(),
        )
        .map_err(|e| io_err(out_dir.display(), e))?;
        Ok(failed)
    }
}
