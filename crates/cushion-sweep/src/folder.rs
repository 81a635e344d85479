//! The output folder above the engine: its lock, the chunk files and their journal, resume,
//! the final files (Parquet and CSV summaries, trajectories, provenance, the report's charts),
//! and the merge of shards. Every file is written atomically.

pub(crate) mod invocations;
pub mod journal;
pub mod mcap_copy;
pub mod merge;
pub mod out_lock;
pub mod parquet_io;
pub mod provenance;
pub mod report;
pub mod runner;
