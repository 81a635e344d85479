//! `cushion sweep FILE [--out DIR] [--threads N] [--resume] [--shard K/N] [--quiet]`: run a
//! sweep file in parallel (see `cushion_sweep::runner` for what lands on disk).

use std::path::PathBuf;

use cushion_sweep::{run_sweep, SweepOptions};

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
    let opts = SweepOptions {
        file: args.file,
        out: args.out,
        threads: args.threads,
        resume: args.resume,
        shard: args.shard,
        quiet: args.quiet,
    };
    match run_sweep(&opts) {
        Ok(o) => {
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
            0
        }
        Err(e) => {
            eprintln!("cushion sweep: {e}");
            e.exit_code()
        }
    }
}
