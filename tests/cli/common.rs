//! What the end-to-end tests share: the built `cushion` command, the repository's folder, and
//! readers of the files the command writes.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use arrow_array::RecordBatch;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

/// The `cushion` binary cargo built for these tests.
pub const BIN: &str = env!("CARGO_BIN_EXE_cushion");

/// The repository's top folder (shipped scenes and sweeps are under `sweeps/`).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The paper's hydraulic scene at a dead time of 70 ms, the base of the tests' sweeps and
/// questions.
pub fn paper_scene() -> PathBuf {
    root().join("sweeps/scenes/paper-hydraulic-dt70.toml")
}

/// Run `cushion ARGS` to its end.
pub fn cushion(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().expect("cushion runs")
}

/// Assert that a run exited 0, showing its output if not.
pub fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A JSON file's contents (`provenance.json`, `answer.json`, an invocation's record).
pub fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_slice(&fs::read(p).unwrap()).unwrap()
}

/// Every record batch of a parquet file, in order.
pub fn read_batches(p: &Path) -> Vec<RecordBatch> {
    let f = fs::File::open(p).unwrap();
    ParquetRecordBatchReaderBuilder::try_new(f)
        .unwrap()
        .build()
        .unwrap()
        .map(|b| b.unwrap())
        .collect()
}
