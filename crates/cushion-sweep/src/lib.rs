//! `cushion-sweep`: sweep files, sampling, the parallel runner, and the output sinks shared by
//! `cushion simulate` and `cushion sweep` (Parquet/CSV summaries, CSV and MCAP trajectories, SVG
//! figures).

// Output sinks for one run (used by `cushion simulate` and by recorded sweep runs).
pub mod figure;
pub mod trajectory_csv;
pub mod trajectory_mcap;

// Sweeps.
pub mod atomic;
mod invocations;
pub mod merge;
pub mod out_lock;
pub mod report;
pub mod runner;
pub mod sampling;
pub mod summary_table;
pub mod sweep_file;

pub use runner::{run_sweep, SweepError, SweepOptions, SweepOutcome};
