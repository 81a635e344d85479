//! Subcommands. Each returns the process exit status.

mod merge;
mod simulate;
mod sweep;

use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "cushion",
    version,
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
}

pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Command::Simulate(a) => simulate::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => merge::run(a),
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
