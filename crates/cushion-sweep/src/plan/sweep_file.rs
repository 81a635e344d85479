//! Sweep files (TOML): what to vary, how to sample it and what to record.
//!
//! ```toml
//! name = "design-space"                   # optional; default: the file's stem
//! scene = "scenes/paper-hydraulic.toml"   # optional base scene, relative to this file, or a
//!                                         # table of scene keys (`scene = { module = "bistable" }`)
//! [set]                                   # optional overrides of the base scene (docs/scene-keys.md)
//! "solver.rtol" = 1e-6
//! [sampling]
//! mode = "sobol"                          # grid (default) | zip | lhs | sobol | saltelli
//! samples = 4096                          # lhs, sobol and saltelli (base points, a power of two)
//! seed = 7                                # lhs, sobol and saltelli (default 0)
//! second_order = true                     # saltelli only (default true)
//! [[axis]]
//! key = "robot.dead_time"
//! linspace = [0.0, 0.1, 11]               # or values = [...], logspace = [start, stop, n], range = [low, high]
//! [output]
//! record = "none"                         # "none" | "all" | [run numbers]: trajectories to MCAP
//! chunk_size = 256                        # runs per chunk (the unit of progress saved on disk)
//! invalid_runs = "fail"                   # "fail": a run whose scene is rejected fails the file
//!                                         # before any run; "row": it becomes a row with status invalid
//! sample_interval = 1e-4                  # recorded runs: also sample every 0.1 ms (default: steps and events)
//! ```
//!
//! Axis forms:
//! - `values = [...]`: numbers, strings (e.g. `module`) or booleans, all of one kind.
//! - `linspace = [start, stop, n]`: `n` evenly spaced values, both ends included (`n = 1`: `start`).
//! - `logspace = [start, stop, n]`: `n` values evenly spaced in log, both **endpoints** given as
//!   values (not exponents): `logspace = [300, 1e5, 8]` runs 300 Pa ... 100 kPa. Both > 0.
//! - `range = [low, high]` (lhs, sobol and saltelli only), with `scale = "linear"` (default) or
//!   `"log"`, or a distribution truncated to the range: `dist = "uniform"` (default),
//!   `"loguniform"` (= `scale = "log"`), `"normal"` (`mean`, `sd`), `"lognormal"` (`median`,
//!   `sigma`), `"triangular"` (`mode`). A normal or lognormal may omit `range` (untruncated),
//!   unless the key must be positive and the distribution could draw below zero.
//!
//! Modes: `grid` is the Cartesian product, first axis slowest (run 0 takes every axis's first
//! value); `zip` takes the i-th value of every axis for run i (all axes the same length); `lhs`
//! (Latin hypercube, seeded ChaCha8) and `sobol` (Owen-scrambled Sobol, seeded) draw `samples`
//! points in the unit cube, one dimension per axis. There, a `range` axis maps its coordinate
//! onto `[low, high]` (log-uniformly with `scale = "log"`), and a list axis (`values`,
//! `linspace`, `logspace`, e.g. categorical `module`) takes value `floor(u * k)` of its `k`
//! values, so every value is drawn evenly (exactly evenly with lhs when `k` divides `samples`).
//! A `range` axis with a distribution takes its inverse CDF of the coordinate. `saltelli`
//! (`cushion-sensitivity`) runs `samples` base points in SALib's Saltelli layout, `N (2D + 2)`
//! runs (`N (D + 2)` with `second_order = false`), with `range` axes only; a `[sensitivity]`
//! table tells `cushion sensitivity` what to analyse.
//!
//! Run numbers are 0-based. Every error names the key (and the axis number), and TOML syntax
//! errors name the line.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use cushion_model::Scene;
use cushion_sensitivity::{block_len, Marginal};
use toml::Value;

mod axes;
mod axis;
mod document;
mod output;
mod sampling;
mod scene;
pub mod toml_helpers;

use axes::parse_axes;
pub use axis::{linspace, logspace};
use document::{parse_document, parse_name, parse_sensitivity};
use output::{parse_output, parse_record};
use sampling::parse_sampling;
use scene::parse_scene_and_set;

/// How the runs are drawn from the axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Grid,
    Zip,
    Lhs,
    Sobol,
    /// SALib's Saltelli layout over a scrambled Sobol sequence (`cushion-sensitivity`).
    Saltelli,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Grid => "grid",
            Mode::Zip => "zip",
            Mode::Lhs => "lhs",
            Mode::Sobol => "sobol",
            Mode::Saltelli => "saltelli",
        }
    }
}

/// One axis's values.
#[derive(Clone, Debug, PartialEq)]
pub enum AxisValues {
    /// A finite list (`values`, `linspace`, `logspace`).
    List(Vec<Value>),
    /// A continuous range (lhs and sobol only).
    Range { low: f64, high: f64, log: bool },
}

/// The kind of value an axis puts in its summary column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisKind {
    Number,
    Text,
    Bool,
}

/// One `[[axis]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub key: String,
    pub values: AxisValues,
    pub kind: AxisKind,
}

/// Which runs record their trajectories.
#[derive(Clone, Debug, PartialEq)]
pub enum Record {
    None,
    All,
    Runs(BTreeSet<u64>),
}

impl Record {
    pub fn wants(&self, run: u64) -> bool {
        match self {
            Record::None => false,
            Record::All => true,
            Record::Runs(r) => r.contains(&run),
        }
    }
    pub fn any(&self) -> bool {
        match self {
            Record::None => false,
            Record::All => true,
            Record::Runs(r) => !r.is_empty(),
        }
    }
}

/// What to do with a run whose scene the model rejects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InvalidRuns {
    /// The sweep file is invalid: fail before any run (default).
    Fail,
    /// The run becomes a row with status `invalid` and the message.
    Row,
}

/// Default runs per chunk.
pub const DEFAULT_CHUNK_SIZE: usize = 256;
/// Sobol points available from `sobol_burley`.
pub const SOBOL_MAX_SAMPLES: u64 = 1 << 16;
/// The largest sweep accepted (a guard against a typo in a grid).
pub const MAX_RUNS: u64 = 1 << 32;

/// A parsed, checked sweep file.
#[derive(Clone, Debug)]
pub struct SweepFile {
    pub name: String,
    /// Where the file was read from.
    pub path: PathBuf,
    /// The file's text, as read (copied next to the results).
    pub text: String,
    /// The base scene with `[set]` applied.
    pub base: Scene,
    /// `[set]` overrides, in file order, flattened to `section.name` keys.
    pub set: Vec<(String, Value)>,
    pub mode: Mode,
    /// lhs and sobol: the points; saltelli: the base points `N` (the runs are `N (2D + 2)`, or
    /// `N (D + 2)` without second order).
    pub samples: u64,
    pub seed: u64,
    pub axes: Vec<Axis>,
    /// Per axis: its distribution when it has one beyond uniform and loguniform (`dist =
    /// "normal" | "lognormal" | "triangular"`), drawn by the inverse CDF of its unit coordinate.
    pub marginals: Vec<Option<Marginal>>,
    /// saltelli: the sample holds the `BA` rows for second-order indices (default true).
    pub second_order: bool,
    /// The `[sensitivity]` table, as written (read by `cushion sensitivity`).
    pub sensitivity: Option<toml::Table>,
    pub record: Record,
    pub chunk_size: usize,
    pub invalid_runs: InvalidRuns,
    /// Recorded runs: also sample the dense output every this many seconds.
    pub sample_interval: Option<f64>,
}

impl SweepFile {
    /// Read and check a sweep file. The error is the whole message (naming the file, key, line).
    pub fn from_file(path: &Path) -> Result<SweepFile, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        SweepFile::from_str_at(&text, path).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parse sweep text; `path` locates the base scene (relative to its folder).
    ///
    /// Each phase stops at its first error, so a file with several problems reports the first
    /// one in the order below.
    pub fn from_str_at(text: &str, path: &Path) -> Result<SweepFile, String> {
        let doc = parse_document(text)?;
        let name = parse_name(&doc, path)?;
        let (base, set) = parse_scene_and_set(&doc, path)?;
        let sampling = parse_sampling(&doc)?;
        let (axes, marginals) = parse_axes(&doc, &sampling, &base, &set)?;
        let sensitivity = parse_sensitivity(&doc)?;
        let output = parse_output(&doc)?;

        let mut sweep = SweepFile {
            name,
            path: path.to_path_buf(),
            text: text.to_string(),
            base,
            set,
            mode: sampling.mode,
            samples: sampling.samples,
            seed: sampling.seed,
            axes,
            marginals,
            second_order: sampling.second_order,
            sensitivity,
            record: Record::None,
            chunk_size: output.chunk_size,
            invalid_runs: output.invalid_runs,
            sample_interval: output.sample_interval,
        };
        // `record` names run numbers, so it is checked against the runs the rest describes.
        let n_runs = sweep.n_runs()?;
        sweep.record = parse_record(output.record, n_runs)?;
        Ok(sweep)
    }

    /// Number of runs the file describes.
    pub fn n_runs(&self) -> Result<u64, String> {
        match self.mode {
            Mode::Grid => {
                let mut n: u64 = 1;
                for a in &self.axes {
                    n = n
                        .checked_mul(list_len(a) as u64)
                        .filter(|n| *n <= MAX_RUNS)
                        .ok_or_else(|| {
                            format!("the grid has more than {MAX_RUNS} runs; use lhs or sobol")
                        })?;
                }
                Ok(n)
            }
            Mode::Zip => Ok(self.axes.first().map(|a| list_len(a) as u64).unwrap_or(1)),
            Mode::Lhs | Mode::Sobol => Ok(self.samples),
            Mode::Saltelli => {
                Ok(self.samples * block_len(self.axes.len(), self.second_order) as u64)
            }
        }
    }
}

fn list_len(a: &Axis) -> usize {
    match &a.values {
        AxisValues::List(v) => v.len(),
        AxisValues::Range { .. } => 0,
    }
}

#[cfg(test)]
mod tests;
