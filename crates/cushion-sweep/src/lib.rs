//! `cushion-sweep`: sweep files, sampling, a compute-only parallel engine, the file layer above
//! it, and the output sinks shared by `cushion simulate`, `cushion sweep` and the Python package
//! (Parquet/CSV summaries, CSV and MCAP trajectories, SVG figures).
//!
//! Layers, each a folder (with `error`, what can go wrong, and `atomic`, how every file is
//! written, beside them):
//! - `plan/`: what to run: `sweep_file` and `sampling`, `runs` (which runs), `summary_table`
//!   (the rows' columns);
//! - `engine`: runs a sweep in memory and returns Arrow record batches, with a progress
//!   callback and a cancel flag;
//! - `folder/`: the output folder: `out_lock`, `journal` (chunk files), `parquet_io`,
//!   `provenance`, `report`, `merge` and `runner` (lock, chunks, resume, final files);
//! - `sinks/`: one run's trajectories (CSV, MCAP) and figures, also used by `cushion simulate`.
//!
//! The library never prints, never exits the process and spawns no program: warnings come back
//! in the outcome, and the caller decides what the user sees.

// The layers, each a folder (see above); their modules keep their paths at the crate's root.
pub mod atomic;
pub mod engine;
pub mod error;
pub mod folder;
pub mod plan;
pub mod sinks;

pub(crate) use folder::invocations;
pub use folder::{journal, mcap_copy, merge, out_lock, parquet_io, provenance, report, runner};
pub use plan::{runs, sampling, summary_table, sweep_file};
pub use sinks::{figure, mcap_read, quantities, trajectory_csv, trajectory_mcap};

pub use engine::{compute, compute_scenes, Hooks, Plan};
pub use error::SweepError;
pub use runner::{run_sweep, SweepOptions, SweepOutcome};
pub use runs::Runs;
pub use sweep_file::SweepFile;
