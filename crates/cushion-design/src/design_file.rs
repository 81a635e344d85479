//! Design files (TOML): a design question asked of the model.
//!
//! ```toml
//! name = "design-question"                # optional; default: the file's stem
//! scene = "scenes/paper-hydraulic.toml"   # base scene, relative to this file (as in a sweep file)
//! [set]                                   # optional overrides of the base scene
//! "solver.rtol" = 1e-6
//! [[design]]                              # 1 to 4: the keys the designer chooses
//! key = "hydraulic.gas_pressure"
//! range = [300.0, 1e5]                    # or values = [...] (numbers or strings: module names)
//! scale = "log"                           # optional, with range: "linear" (default) or "log"
//! [[for_all]]                             # the conditions every design must survive
//! key = "object.mass"
//! range = [0.05, 1.0]
//! [[limit]]                               # 1 or more
//! metric = "peak_robot_force"             # any numeric summary field
//! max = 40.0                              # and/or min
//! abs = true                              # limit the size |value| (default false)
//! [objective]                             # optional: minimize or maximize = "metric"
//! minimize = "peak_robot_force"           # the worst case over the for_all box, among feasible designs
//! [search]                                # optional
//! resolution = 0.015625                   # the finest design cell, a fraction of each range (1/64)
//! tolerance = 1e-3                        # how close the worst cases must come, relative
//! verify = 41                             # points per for_all range of the verification grid
//! ```
//!
//! `name`, `scene` and `[set]`, and each axis's key and values, are checked by the sweep file's
//! own parser (`cushion_sweep::SweepFile`), so a design file and a sweep file accept and refuse
//! the same keys and values; then every value of every axis is set on the base scene and
//! checked. The question itself (limits, objective, search settings, the boxes) is checked by
//! the search core's constructors. Every error names the table, the key, the value and what is
//! allowed; TOML syntax errors name the line.

use std::path::{Path, PathBuf};

use cushion_model::{Cell, Scene, Summary};
use cushion_sweep::sweep_file::toml_helpers::{as_number, check_keys};
use cushion_sweep::sweep_file::{Axis as SweepAxis, AxisValues};
use cushion_sweep::SweepFile;
use toml::Value;

use crate::axes::{Axes, Axis};
use crate::limits::{Limit, Limits, Objective};
use crate::refine::{RefineSettings, Refinement};
use crate::worst_case::SearchSettings;

mod goals;
mod search;

use goals::{limits, objective};
use search::search;

/// The most design axes a question takes.
pub const MAX_DESIGN_AXES: usize = 4;
/// The default verification grid: points per `for_all` range.
pub const DEFAULT_VERIFY: usize = 41;

/// `[search]`: how finely the design space is mapped and the worst cases searched for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchOptions {
    /// The finest design cell, as a fraction of each design range (default 1/64).
    pub resolution: f64,
    /// How close to the true worst case the search must come, relative (default 1e-3).
    pub tolerance: f64,
    /// Points per `for_all` range of the grid the chosen design is verified on (default 41).
    pub verify: usize,
}

impl Default for SearchOptions {
    fn default() -> SearchOptions {
        SearchOptions {
            resolution: 1.0 / 64.0,
            tolerance: 1e-3,
            verify: DEFAULT_VERIFY,
        }
    }
}

/// A parsed, checked design file.
#[derive(Clone, Debug)]
pub struct DesignFile {
    pub name: String,
    /// Where the file was read from.
    pub path: PathBuf,
    /// The file's text, as read (copied next to the results).
    pub text: String,
    /// The base scene with `[set]` applied.
    pub base: Scene,
    /// `[set]` overrides, in file order, flattened to `section.name` keys.
    pub set: Vec<(String, Value)>,
    /// `[[design]]`, in file order (a sweep file's axis: key, range or list of values).
    pub design: Vec<SweepAxis>,
    /// `[[for_all]]`, in file order.
    pub for_all: Vec<SweepAxis>,
    pub limits: Vec<Limit>,
    pub objective: Option<Objective>,
    pub search: SearchOptions,
}

/// The summary fields a limit may name: those whose cells are numbers (floats and counts).
pub fn numeric_metrics() -> Vec<&'static str> {
    Summary::COLUMNS
        .iter()
        .zip(Summary::invalid("").cells())
        .filter(|(_, c)| matches!(c, Cell::Float(_) | Cell::Int(_)))
        .map(|(n, _)| *n)
        .collect()
}

/// An array of tables `[[what]]` (absent: empty).
fn tables<'a>(doc: &'a toml::Table, what: &str) -> Result<Vec<&'a toml::Table>, String> {
    match doc.get(what) {
        None => Ok(Vec::new()),
        Some(Value::Array(a)) => a
            .iter()
            .enumerate()
            .map(|(i, v)| {
                v.as_table()
                    .ok_or_else(|| format!("[[{what}]] #{}: must be a table, got {v}", i + 1))
            })
            .collect(),
        Some(other) => Err(format!(
            "`{what}` must be an array of tables [[{what}]], got {other}"
        )),
    }
}

impl DesignFile {
    /// Read and check a design file. The error is the whole message (naming the file, the key,
    /// the value and what is allowed).
    pub fn from_file(path: &Path) -> Result<DesignFile, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        DesignFile::from_str_at(&text, path).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parse design text; `path` locates the base scene (relative to its folder) and gives the
    /// default name (its stem).
    pub fn from_str_at(text: &str, path: &Path) -> Result<DesignFile, String> {
        let doc: toml::Table = match text.parse() {
            Ok(d) => d,
            // The sweep parser words TOML syntax errors (line and column); let it.
            Err(e) => {
                return Err(SweepFile::from_str_at(text, path)
                    .err()
                    .unwrap_or_else(|| format!("TOML syntax error: {e}")))
            }
        };
        check_keys(
            &doc,
            &[
                "name",
                "scene",
                "set",
                "design",
                "for_all",
                "limit",
                "objective",
                "search",
            ],
            "the design file",
        )?;

        // name, scene and [set]: the sweep file's parser, on just those keys.
        let mut head = toml::Table::new();
        for k in ["name", "scene", "set"] {
            if let Some(v) = doc.get(k) {
                head.insert(k.to_string(), v.clone());
            }
        }
        let head = SweepFile::from_str_at(&to_text(&head)?, path)?;

        let design = axes(&doc, "design", &head, &[])?;
        let for_all = axes(&doc, "for_all", &head, &design)?;
        if design.is_empty() {
            return Err(
                "[[design]]: none given; give 1 to 4 design axes (key with range or values)".into(),
            );
        }
        if design.len() > MAX_DESIGN_AXES {
            return Err(format!(
                "[[design]]: {} axes given; a design question takes 1 to {MAX_DESIGN_AXES}",
                design.len()
            ));
        }
        if for_all.is_empty() {
            return Err("[[for_all]]: none given; give at least one condition (key with range or values) the design must survive".into());
        }

        let limits = limits(&doc)?;
        let objective = objective(&doc)?;
        let search = search(&doc)?;

        let file = DesignFile {
            name: head.name,
            path: path.to_path_buf(),
            text: text.to_string(),
            base: head.base,
            set: head.set,
            design,
            for_all,
            limits,
            objective,
            search,
        };
        // The question as the search core sees it: its constructors check the rest (a range
        // low < high, min <= max, the objective on a limited metric, the settings).
        file.refinement().map_err(|e| e.to_string())?;
        Ok(file)
    }

    /// The design axes as the search sees them (a list axis by its number of values).
    pub fn design_axes(&self) -> Result<Axes, crate::DesignError> {
        Axes::new("design", self.design.iter().map(core_axis).collect())
    }

    /// The `for_all` box as the search sees it.
    pub fn for_all_axes(&self) -> Result<Axes, crate::DesignError> {
        Axes::new("for_all", self.for_all.iter().map(core_axis).collect())
    }

    /// The limits and the objective, checked.
    pub fn checked_limits(&self) -> Result<Limits, crate::DesignError> {
        Limits::new(self.limits.clone(), self.objective.clone())
    }

    /// The search settings of `[search]`.
    pub fn refine_settings(&self) -> RefineSettings {
        RefineSettings {
            resolution: self.search.resolution,
            initial_cells: None,
            search: SearchSettings {
                tolerance: self.search.tolerance,
                ..SearchSettings::default()
            },
        }
    }

    /// A fresh refinement of this question, ready for its first `ask`.
    pub fn refinement(&self) -> Result<Refinement, crate::DesignError> {
        let r = Refinement::new(
            self.design_axes()?,
            self.for_all_axes()?,
            self.checked_limits()?,
            self.refine_settings(),
        )?;
        crate::verify::verify_grid(r.for_all(), self.search.verify)?;
        Ok(r)
    }
}

/// The scene value of coordinate `x` along `axis` (a point of the search in real units): the
/// number along a range, the value of index `x` along a list.
pub fn scene_value(axis: &SweepAxis, x: f64) -> Value {
    match &axis.values {
        AxisValues::Range { .. } => Value::Float(x),
        AxisValues::List(vals) => vals[(x.max(0.0) as usize).min(vals.len() - 1)].clone(),
    }
}

fn core_axis(a: &SweepAxis) -> Axis {
    match &a.values {
        AxisValues::Range { low, high, log } if *log => Axis::log_range(&a.key, *low, *high),
        AxisValues::Range { low, high, .. } => Axis::range(&a.key, *low, *high),
        AxisValues::List(v) => Axis::values(&a.key, v.len()),
    }
}

fn to_text(t: &toml::Table) -> Result<String, String> {
    toml::to_string(t).map_err(|e| format!("internal error: cannot write TOML: {e}"))
}

/// `[[design]]` or `[[for_all]]`: each axis checked by the sweep parser (key, values), then
/// against `[set]` and the design axes (for `for_all`), then each of its values set on the
/// base scene.
fn axes(
    doc: &toml::Table,
    what: &str,
    head: &SweepFile,
    design: &[SweepAxis],
) -> Result<Vec<SweepAxis>, String> {
    let mut out: Vec<SweepAxis> = Vec::new();
    for (i, t) in tables(doc, what)?.into_iter().enumerate() {
        let key = t.get("key").and_then(Value::as_str).unwrap_or("?");
        let label = format!("[[{what}]] #{} (`{key}`)", i + 1);
        check_keys(t, &["key", "range", "scale", "values"], &label)?;
        // One axis as a sampled sweep's (where `range` is allowed); its messages say
        // `[[axis]] #1`, which is this table.
        let mut sweep = toml::Table::new();
        let mut sampling = toml::Table::new();
        sampling.insert("mode".into(), Value::String("lhs".into()));
        sampling.insert("samples".into(), Value::Integer(1));
        sweep.insert("sampling".into(), Value::Table(sampling));
        sweep.insert("axis".into(), Value::Array(vec![Value::Table(t.clone())]));
        let parsed = SweepFile::from_str_at(&to_text(&sweep)?, &head.path).map_err(|e| {
            let e = e.replacen("[[axis]] #1", &format!("[[{what}]] #{}", i + 1), 1);
            if e.starts_with(&format!("[[{what}]]")) {
                e
            } else {
                format!("[[{what}]] #{}: {e}", i + 1)
            }
        })?;
        let mut axis = parsed.axes.into_iter().next().ok_or_else(|| {
            format!(
                "[[{what}]] #{}: missing `key` and `range` or `values`",
                i + 1
            )
        })?;
        // The sweep parser took the values from the text it was given; take the numbers from
        // the file itself, so no value passes through a second formatting.
        match (&mut axis.values, t.get("range").and_then(Value::as_array)) {
            (AxisValues::Range { low, high, .. }, Some(r)) if r.len() == 2 => {
                *low = as_number(&r[0]).unwrap_or(*low);
                *high = as_number(&r[1]).unwrap_or(*high);
            }
            (AxisValues::List(vals), None) => {
                if let Some(Value::Array(v)) = t.get("values") {
                    *vals = v.clone();
                }
            }
            _ => {}
        }
        if out.iter().any(|a| a.key == axis.key) {
            return Err(format!(
                "{label}: the key has another [[{what}]] axis already"
            ));
        }
        if design.iter().any(|d| d.key == axis.key) {
            return Err(format!(
                "{label}: the key is also a [[design]] axis; a key is chosen or survived, keep it in one"
            ));
        }
        if head.set.iter().any(|(k, _)| k == &axis.key) {
            return Err(format!("{label}: the key is also in [set]; keep one"));
        }
        let values: Vec<Value> = match &axis.values {
            AxisValues::Range { low, high, .. } => vec![Value::Float(*low), Value::Float(*high)],
            AxisValues::List(v) => v.clone(),
        };
        for v in &values {
            let mut scene = head.base.clone();
            scene
                .set(&axis.key, v)
                .and_then(|()| scene.validate())
                .map_err(|e| format!("{label}: value {v}: {e}"))?;
        }
        out.push(axis);
    }
    Ok(out)
}
