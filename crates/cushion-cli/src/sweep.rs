//! `cushion sweep FILE [--out DIR] [--threads N] [--resume] [--shard K/N] [--quiet]`: run a
//! sweep file in parallel (see `cushion_sweep::runner` for what lands on disk). This command
//! draws the progress bar, prints the warnings and the closing line, and finds the git commit
//! for the provenance; the library does none of that.

use std::path::PathBuf;

use cushion_sweep::{run_sweep, Hooks, SweepError, SweepFile, SweepOptions};

#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// The sweep file (TOML; see sweeps/*.toml).
    pub file: PathBuf,
    /// Output folder (default: `runs/<sweep name>`).
    #[arg(long, help = "Output folder [default: runs/<sweep name>]")]
    pub out: Option<PathBuf>,
    /// Worker threads [default: all cores]. The results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Continue an interrupted sweep in the same --out, skipping finished chunks.
    #[arg(long)]
    pub resume: bool,
    /// Run only shard K of N (runs with run % N == K - 1); join shards with `cushion merge`.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// No progress bar and no closing line.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Print the time of each phase of the sweep on standard error.
const TIMING_ENV: &str = "CUSHION_SWEEP_TIMING";

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let err = || format!("`{s}`: expected K/N with 1 <= K <= N, e.g. 2/4");
    let (k, n) = s.split_once('/').ok_or_else(err)?;
    let (k, n): (usize, usize) = (
        k.trim().parse().map_err(|_| err())?,
        n.trim().parse().map_err(|_| err())?,
    );
    if k == 0 || n == 0 || k > n {
        return Err(err());
    }
    Ok((k, n))
}

pub fn run(args: SweepArgs) -> i32 {
    match run_inner(&args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("cushion sweep: {e}");
            e.exit_code()
        }
    }
}

fn run_inner(args: &SweepArgs) -> Result<(), SweepError> {
    if args.threads == Some(0) {
        return Err(SweepError::Config("--threads must be at least 1".into()));
    }
    let sweep = SweepFile::from_file(&args.file).map_err(SweepError::Config)?;
    let opts = SweepOptions {
        out: args.out.clone(),
        threads: args.threads,
        resume: args.resume,
        shard: args.shard,
        git_commit: super::git_commit(),
    };
    let bar = crate::progress::RunsBar::new(args.quiet, true);
    let progress = |done: u64, total: u64| bar.update(done, total);
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: Some(&super::INTERRUPTED),
        chunk_written: Some(&super::chunk_written),
    };
    let result = run_sweep(sweep, &opts, &hooks);
    bar.finish();
    let o = result?;
    for w in &o.warnings {
        eprintln!("cushion sweep: warning: {w}");
    }
    if std::env::var_os(TIMING_ENV).is_some() {
        for (what, seconds) in &o.phases {
            eprintln!("cushion sweep: {what}: {seconds:.3} s");
        }
    }
    if !args.quiet {
        println!(
            "{}: {} runs ({} computed now, {} not ok) in {:.2} s",
            o.out_dir.display(),
            o.runs_total,
            o.runs_done_now,
            o.runs_failed,
            o.wall_seconds
        );
    }
    Ok(())
}
