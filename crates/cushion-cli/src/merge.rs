//! `cushion merge DIR... [--out DIR]`: join the outputs of `cushion sweep --shard K/N` into one
//! summary equal to the unsharded sweep's.

use std::path::PathBuf;

use cushion_sweep::merge::{merge, MergeOptions};

#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// The shards' output folders (all N of them, any order).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output folder (default: `runs/<sweep name>`).
    #[arg(long, help = "Output folder [default: runs/<sweep name>]")]
    pub out: Option<PathBuf>,
    /// No closing line.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: MergeArgs) -> i32 {
    match merge(&MergeOptions {
        dirs: args.dirs,
        out: args.out,
    }) {
        Ok(o) => {
            for w in &o.warnings {
                eprintln!("cushion merge: warning: {w}");
            }
            if !args.quiet {
                println!(
                    "{}: {} runs merged ({} not ok)",
                    o.out_dir.display(),
                    o.runs,
                    o.runs_failed
                );
            }
            0
        }
        Err(e) => {
            eprintln!("cushion merge: {e}");
            e.exit_code()
        }
    }
}
