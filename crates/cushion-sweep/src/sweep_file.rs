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
use cushion_sensitivity::{block_len, Marginal, SaltelliSample};
use toml::Value;

mod axis;

use axis::parse_axis;
pub use axis::{linspace, logspace};

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

fn type_name(v: &Value) -> &'static str {
    v.type_str()
}

fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

fn check_keys(table: &toml::Table, allowed: &[&str], where_: &str) -> Result<(), String> {
    for k in table.keys() {
        if !allowed.contains(&k.as_str()) {
            return Err(format!(
                "unknown key `{k}` in {where_} (allowed: {})",
                allowed.join(", ")
            ));
        }
    }
    Ok(())
}

/// Flatten `{solver = {rtol = 1e-6}}` (unquoted dotted keys) into `solver.rtol`.
fn flatten(prefix: &str, t: &toml::Table, out: &mut Vec<(String, Value)>) {
    for (k, v) in t {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            Value::Table(inner) => flatten(&key, inner, out),
            _ => out.push((key, v.clone())),
        }
    }
}

impl SweepFile {
    /// Read and check a sweep file. The error is the whole message (naming the file, key, line).
    pub fn from_file(path: &Path) -> Result<SweepFile, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        SweepFile::from_str_at(&text, path).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parse sweep text; `path` locates the base scene (relative to its folder).
    pub fn from_str_at(text: &str, path: &Path) -> Result<SweepFile, String> {
        let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            // One line: "line L, column C: what".
            let msg = e.message().trim().replace('\n', "; ");
            match e.span() {
                Some(span) => {
                    let before = &text[..span.start.min(text.len())];
                    let line = before.matches('\n').count() + 1;
                    let col = before.len() - before.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
                    format!("TOML syntax error at line {line}, column {col}: {msg}")
                }
                None => format!("TOML syntax error: {msg}"),
            }
        })?;
        check_keys(
            &doc,
            &["name", "scene", "set", "sampling", "axis", "output", "sensitivity"],
            "the sweep file",
        )?;

        let name = match doc.get("name") {
            None => path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "sweep".to_string()),
            Some(Value::String(s)) => s.clone(),
            Some(other) => return Err(format!("`name` must be a string, got {other}")),
        };
        if name.is_empty()
            || name == "."
            || name == ".."
            || name.contains(['/', '\\'])
            || name.chars().any(|c| c.is_control())
        {
            return Err(format!(
                "`name` = {name:?}: must be a plain folder name (no slashes), it names runs/<name>"
            ));
        }

        let mut base = match doc.get("scene") {
            None => Scene::default(),
            Some(Value::String(s)) => {
                let dir = path.parent().unwrap_or(Path::new(""));
                let scene_path = dir.join(s);
                Scene::from_file(&scene_path).map_err(|e| format!("`scene` = {s:?}: {e}"))?
            }
            Some(Value::Table(t)) => {
                let mut scene = Scene::default();
                scene.apply_table(t).map_err(|e| format!("`scene`: {e}"))?;
                scene
            }
            Some(other) => {
                return Err(format!(
                    "`scene` must be a path string or a table of scene keys, got {other}"
                ))
            }
        };

        let mut set = Vec::new();
        if let Some(v) = doc.get("set") {
            let t = v.as_table().ok_or("`set` must be a table [set]")?;
            flatten("", t, &mut set);
        }
        for (k, v) in &set {
            base.set(k, v).map_err(|e| format!("[set] {e}"))?;
        }

        // [sampling]
        let empty = toml::Table::new();
        let sampling = match doc.get("sampling") {
            None => &empty,
            Some(Value::Table(t)) => t,
            Some(_) => return Err("`sampling` must be a table [sampling]".to_string()),
        };
        check_keys(
            sampling,
            &["mode", "samples", "seed", "second_order"],
            "[sampling]",
        )?;
        let mode = match sampling.get("mode") {
            None => Mode::Grid,
            Some(Value::String(s)) => match s.as_str() {
                "grid" => Mode::Grid,
                "zip" => Mode::Zip,
                "lhs" => Mode::Lhs,
                "sobol" => Mode::Sobol,
                "saltelli" => Mode::Saltelli,
                _ => {
                    return Err(format!(
                        "[sampling] mode = {s:?}: allowed \"grid\", \"zip\", \"lhs\", \"sobol\", \"saltelli\""
                    ))
                }
            },
            Some(other) => {
                return Err(format!(
                    "[sampling] mode = {other}: allowed \"grid\", \"zip\", \"lhs\", \"sobol\", \"saltelli\""
                ))
            }
        };
        let random = matches!(mode, Mode::Lhs | Mode::Sobol | Mode::Saltelli);
        let samples = match (sampling.get("samples"), random) {
            (None, true) => {
                return Err(format!("[sampling] mode {} needs `samples` (an integer >= 1)", mode.name()))
            }
            (None, false) => 0,
            (Some(_), false) => {
                return Err(format!(
                    "[sampling] `samples` is for lhs, sobol and saltelli only (mode is {}: the axes set the number of runs)",
                    mode.name()
                ))
            }
            (Some(Value::Integer(n)), true) if *n >= 1 => *n as u64,
            (Some(other), true) => {
                return Err(format!("[sampling] samples = {other}: must be an integer >= 1"))
            }
        };
        if mode == Mode::Sobol && samples > SOBOL_MAX_SAMPLES {
            return Err(format!(
                "[sampling] samples = {samples}: sobol gives at most {SOBOL_MAX_SAMPLES} points; use lhs for more"
            ));
        }
        if samples > MAX_RUNS {
            return Err(format!(
                "[sampling] samples = {samples}: at most {MAX_RUNS}"
            ));
        }
        let seed = match (sampling.get("seed"), random) {
            (None, _) => 0,
            (Some(_), false) => {
                return Err(format!(
                    "[sampling] `seed` is for lhs, sobol and saltelli only (mode is {})",
                    mode.name()
                ))
            }
            (Some(Value::Integer(n)), true) if *n >= 0 && (*n as u64) <= u32::MAX as u64 => {
                *n as u64
            }
            (Some(other), true) => {
                return Err(format!(
                    "[sampling] seed = {other}: must be an integer from 0 to {}",
                    u32::MAX
                ))
            }
        };

        if mode == Mode::Saltelli && !samples.is_power_of_two() {
            return Err(format!(
                "[sampling] samples = {samples}: saltelli takes a power of two (base points) from 1 to {}",
                SaltelliSample::MAX_BASE_POINTS
            ));
        }
        let second_order = match (sampling.get("second_order"), mode) {
            (None, _) => true,
            (Some(Value::Boolean(b)), Mode::Saltelli) => *b,
            (Some(Value::Boolean(_)), _) => {
                return Err(format!(
                    "[sampling] `second_order` is for saltelli only (mode is {})",
                    mode.name()
                ))
            }
            (Some(other), _) => {
                return Err(format!(
                    "[sampling] second_order = {other}: must be true or false"
                ))
            }
        };

        // [[axis]]
        let mut axes = Vec::new();
        let mut marginals = Vec::new();
        match doc.get("axis") {
            None => {}
            Some(Value::Array(arr)) => {
                for (i, v) in arr.iter().enumerate() {
                    let (axis, marginal) = parse_axis(i, v, mode, &base)?;
                    axes.push(axis);
                    marginals.push(marginal);
                }
            }
            Some(_) => return Err("`axis` must be an array of tables [[axis]]".to_string()),
        }
        let mut seen = BTreeSet::new();
        for (i, a) in axes.iter().enumerate() {
            if !seen.insert(a.key.clone()) {
                return Err(format!(
                    "[[axis]] #{} (`{}`): the key has another axis already",
                    i + 1,
                    a.key
                ));
            }
            if set.iter().any(|(k, _)| k == &a.key) {
                return Err(format!(
                    "[[axis]] #{} (`{}`): the key is also in [set]; keep one",
                    i + 1,
                    a.key
                ));
            }
        }
        if mode == Mode::Zip {
            if let Some(first) = axes.first() {
                let n0 = list_len(first);
                for (i, a) in axes.iter().enumerate() {
                    if list_len(a) != n0 {
                        return Err(format!(
                            "[[axis]] #{} (`{}`): zip needs axes of one length: it has {} values, `{}` has {}",
                            i + 1,
                            a.key,
                            list_len(a),
                            first.key,
                            n0
                        ));
                    }
                }
            }
        }
        if mode == Mode::Sobol && axes.len() as u32 > sobol_burley::NUM_DIMENSIONS {
            return Err(format!(
                "sobol takes at most {} axes",
                sobol_burley::NUM_DIMENSIONS
            ));
        }

        if mode == Mode::Saltelli {
            SaltelliSample::new(axes.len(), samples as usize, second_order, seed).map_err(|e| {
                match e {
                    cushion_sensitivity::SensitivityError::Config { key, value, allowed }
                        if key == "inputs" =>
                    {
                        format!("[[axis]]: saltelli needs 1 to {} `range` axes, got {value} ({allowed})", SaltelliSample::MAX_INPUTS)
                    }
                    other => format!("[sampling] {other}"),
                }
            })?;
        }
        let sensitivity = match doc.get("sensitivity") {
            None => None,
            Some(Value::Table(t)) => Some(t.clone()),
            Some(_) => return Err("`sensitivity` must be a table [sensitivity]".to_string()),
        };

        // [output]
        let output = match doc.get("output") {
            None => &empty,
            Some(Value::Table(t)) => t,
            Some(_) => return Err("`output` must be a table [output]".to_string()),
        };
        check_keys(
            output,
            &["record", "chunk_size", "invalid_runs", "sample_interval"],
            "[output]",
        )?;
        let sample_interval = match output.get("sample_interval") {
            None => None,
            Some(v) => match as_number(v) {
                Some(x) if x > 0.0 && x.is_finite() => Some(x),
                _ => {
                    return Err(format!(
                        "[output] sample_interval = {v}: must be a number > 0 (seconds)"
                    ))
                }
            },
        };
        let chunk_size = match output.get("chunk_size") {
            None => DEFAULT_CHUNK_SIZE,
            Some(Value::Integer(n)) if *n >= 1 && *n <= 1 << 20 => *n as usize,
            Some(other) => {
                return Err(format!(
                    "[output] chunk_size = {other}: must be an integer from 1 to {}",
                    1 << 20
                ))
            }
        };
        let invalid_runs = match output.get("invalid_runs") {
            None => InvalidRuns::Fail,
            Some(Value::String(s)) if s == "fail" => InvalidRuns::Fail,
            Some(Value::String(s)) if s == "row" => InvalidRuns::Row,
            Some(other) => {
                return Err(format!(
                    "[output] invalid_runs = {other}: allowed \"fail\" or \"row\""
                ))
            }
        };

        let mut sweep = SweepFile {
            name,
            path: path.to_path_buf(),
            text: text.to_string(),
            base,
            set,
            mode,
            samples,
            seed,
            axes,
            marginals,
            second_order,
            sensitivity,
            record: Record::None,
            chunk_size,
            invalid_runs,
            sample_interval,
        };
        let n_runs = sweep.n_runs()?;
        sweep.record = match output.get("record") {
            None => Record::None,
            Some(Value::String(s)) if s == "none" => Record::None,
            Some(Value::String(s)) if s == "all" => Record::All,
            Some(Value::Array(a)) => {
                let mut runs = BTreeSet::new();
                for v in a {
                    match v {
                        Value::Integer(n) if *n >= 0 && (*n as u64) < n_runs => {
                            runs.insert(*n as u64);
                        }
                        other => {
                            return Err(format!(
                                "[output] record: {other} is not a run number (0 to {})",
                                n_runs.saturating_sub(1)
                            ))
                        }
                    }
                }
                Record::Runs(runs)
            }
            Some(other) => {
                return Err(format!(
                    "[output] record = {other}: allowed \"none\", \"all\" or a list of run numbers"
                ))
            }
        };
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
            Mode::Saltelli => Ok(self.samples * block_len(self.axes.len(), self.second_order) as u64),
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
