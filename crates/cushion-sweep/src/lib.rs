//! `cushion-sweep`: sweep files, sampling, a compute-only parallel engine, the file layer above
//! it, and the output sinks shared by `cushion simulate`, `cushion sweep` and the Python package
//! (Parquet/CSV summaries, CSV and MCAP trajectories, SVG figures).
//!
//! Layers, each using only those listed before it:
//! - `error` (what can go wrong), `runs` (which runs), `sweep_file` and `sampling` (what to
//!   run), `summary_table` (the rows' columns);
//! - `engine`: runs a sweep in memory and returns Arrow record batches, with a progress
//!   callback and a cancel flag;
//! - `parquet_io`, `journal` (chunk files), `out_lock`, `provenance`, `report`, `merge` and
//!   `runner` (the output folder: lock, chunks, resume, final files).
//!
//! The library never prints, never exits the process and spawns no program: warnings come back
//! in the outcome, and the caller decides what the user sees.

// Output sinks for one run (used by `cushion simulate` and by recorded sweep runs).
pub mod figure;
pub mod mcap_read;
pub mod trajectory_csv;
pub mod trajectory_mcap;

// What to run.
pub mod error;
pub mod runs;
pub mod sampling;
pub mod summary_table;
pub mod sweep_file;

// Computing it.
pub mod engine;

// The output folder.
pub mod atomic;
mod invocations;
pub mod journal;
pub mod mcap_copy;
pub mod merge;
pub mod out_lock;
pub mod parquet_io;
pub mod provenance;
pub mod report;
pub mod runner;

pub use engine::{compute, compute_scenes, Hooks, Plan};
pub use error::SweepError;
pub use runner::{run_sweep, SweepOptions, SweepOutcome};
pub use runs::Runs;
pub use sweep_file::SweepFile;
