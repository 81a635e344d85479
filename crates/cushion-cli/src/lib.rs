//! The `cushion` command line: clap subcommands over `cushion-model` and `cushion-sweep`, run by
//! the `cushion` binary and by the Python package's console script (`cushion`, `python -m
//! cushion`) through [`run_from`], so both parse and answer alike.
//!
//! Exit status: 0 success, 2 bad input (a message naming the key, value and what is allowed),
//! 1 anything else (I/O; for `simulate`, also a run that ended with a status other than `ok`,
//! whose summary is still printed). Each subcommand returns its status; nothing here exits the
//! process (the Python extension runs this command inside its host).

mod completions;
mod design;
mod merge;
mod progress;
pub mod sensitivity;
mod simulate;
mod sweep;

use std::ffi::OsString;
use std::io::Write;

use clap::{Parser, Subcommand};

/// Called after each chunk a sweep writes, with the count so far; set only by a program that
/// owns its process (the `cushion` binary's abrupt-stop test hook), never by the extension.
static CHUNK_WRITTEN: std::sync::OnceLock<fn(usize)> = std::sync::OnceLock::new();

/// Install the after-chunk hook of `cushion sweep` and `cushion sensitivity` (once; later calls
/// are ignored).
pub fn on_chunk_written(hook: fn(usize)) {
    let _ = CHUNK_WRITTEN.set(hook);
}

/// The installed after-chunk hook, if any, called with the count of chunks written so far.
fn chunk_written(n: usize) {
    if let Some(hook) = CHUNK_WRITTEN.get() {
        hook(n);
    }
}

/// Raised by [`interrupt`]: the long subcommands (`sweep`, `design`, `sensitivity`) pass it to
/// the engine as their cancel flag, so they stop within one chunk (a sweep keeps its finished
/// chunks) or one round of a design search (nothing written).
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Ask the running subcommand to stop; returns whether it had been asked already. The `cushion`
/// binary calls it on Ctrl-C (a second Ctrl-C ends the process at once); the Python extension
/// has its own cancel flag.
pub fn interrupt() -> bool {
    INTERRUPTED.swap(true, std::sync::atomic::Ordering::SeqCst)
}

/// Run the command with these arguments (the first is the program's name, as in `argv`) and
/// return its exit status. Help, `--version` and usage errors are printed as clap prints them,
/// with clap's statuses (0, and 2 for a usage error).
pub fn run_from<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let code = match Cli::try_parse_from(args) {
        Ok(cli) => run(cli),
        Err(e) => {
            let _ = e.print();
            e.exit_code()
        }
    };
    // Inside the Python extension no Rust `main` flushes standard output on the way out.
    let _ = std::io::stdout().flush();
    code
}

#[derive(Parser, Debug)]
#[command(
    name = "cushion",
    version = env!("CUSHION_VERSION_LINE"),
    about = "Robot end-effector collisions with small objects, and the modules that soften them"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run one scene and print its summary.
    Simulate(simulate::SimulateArgs),
    /// Run a sweep file in parallel.
    Sweep(sweep::SweepArgs),
    /// Join sweep shards into one summary.
    Merge(merge::MergeArgs),
    /// Answer a design question: the designs whose searched worst case over the for_all box
    /// meets every limit, the best one, verified.
    Design(design::DesignArgs),
    /// Sobol indices (S1, ST, S2 with confidence intervals) of a saltelli sweep's outputs.
    Sensitivity(sensitivity::SensitivityArgs),
    /// Print a shell completion script (e.g. `cushion completions bash > ~/.local/share/bash-completion/completions/cushion`).
    Completions(completions::CompletionsArgs),
}

pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Command::Simulate(a) => simulate::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Design(a) => design::run(a),
        Command::Sensitivity(a) => sensitivity::run(a),
        Command::Completions(a) => completions::run(a),
    }
}

/// The git commit of the working folder, when there is one (for `provenance.json`).
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
