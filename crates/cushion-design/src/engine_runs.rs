//! A design question answered by the model: every batch the refinement asks for becomes one
//! batch of runs through the sweep crate's parallel engine (`cushion_sweep::compute_scenes`, on
//! one rayon pool for the whole question), then the chosen design is run on the verification
//! grid. Nothing is written here: the output folder is `output.rs`'s.
//!
//! A run's row for the search holds the limited metrics of its summary, in the order of
//! [`crate::Limits::metrics`]; a run whose status is not `ok`, or whose metric has no value
//! (`object_final_velocity` without an object), gives `NaN`, which the search treats as a failed
//! run: it violates every limit. The engine returns each batch in its order and the search
//! decides on the values alone, so the answer is the same for any thread count. Every run made
//! is kept as a row of the sweep's summary table (plus its stage, design and `for_all` values).

use std::time::Instant;

use arrow_array::RecordBatch;
use cushion_model::{simulate, Cell, RunStatus, Scene, Summary};
use cushion_sweep::engine::{compute_scenes, thread_pool, Hooks, Model, RunCount};
use cushion_sweep::summary_table::{RowsBuilder, TableSchema};
use cushion_sweep::sweep_file::{Axis as SweepAxis, AxisKind, AxisValues};
use cushion_sweep::SweepError;
use toml::Value;

use crate::axes::Point;
use crate::design_file::{scene_value, DesignFile};
use crate::refine::{DesignPoint, Refinement};
use crate::verify::{check, verify_grid, Verification};

/// The column of `runs.parquet` that says what a run was for: `search` or `verify`.
pub const STAGE: &str = "stage";

/// A design question answered, in memory.
pub struct DesignResult {
    pub file: DesignFile,
    /// The refined design map: every design point with its worst cases, the cells, the best.
    pub map: Refinement,
    /// The chosen design (see the crate docs for the rule).
    pub best: DesignPoint,
    /// The `for_all` points of the verification grid (real units, indices along lists).
    pub verify_points: Vec<Point>,
    pub verification: Verification,
    /// Every run made, in order (search batches, then verification): the columns of a sweep's
    /// summary with `stage`, the design keys and the `for_all` keys as its axis columns.
    pub runs: Vec<RecordBatch>,
    /// Runs of the search, and of the verification.
    pub search_runs: usize,
    pub verify_runs: usize,
    /// Batches of the search (each one call of the engine).
    pub batches: usize,
    pub threads: usize,
    pub wall_seconds: f64,
}

/// Answer a design question with the real model on `threads` workers (default: every core).
pub fn compute_design(
    file: DesignFile,
    threads: Option<usize>,
    hooks: &Hooks,
) -> Result<DesignResult, SweepError> {
    compute_design_with(file, threads, hooks, &simulate)
}

/// [`compute_design`] with any model function (tests use a stand-in).
pub fn compute_design_with(
    file: DesignFile,
    threads: Option<usize>,
    hooks: &Hooks,
    sim: &Model,
) -> Result<DesignResult, SweepError> {
    let started = Instant::now();
    let (pool, threads) = thread_pool(threads)?;
    let config =
        |e: crate::DesignError| SweepError::Config(format!("{}: {e}", file.path.display()));
    let mut map = file.refinement().map_err(config)?;
    let mut runner = Runner::new(&file, &map, &pool, sim, hooks);

    let mut batches = 0;
    loop {
        if hooks
            .cancel
            .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
        {
            return Err(SweepError::Cancelled);
        }
        let batch = map.ask();
        if batch.is_empty() {
            break;
        }
        let rows = runner.run("search", batch.iter().map(|r| (&r.design, &r.for_all)))?;
        map.tell(rows).map_err(internal)?;
        batches += 1;
    }
    let search_runs = runner.made;
    let best = map
        .best()
        .cloned()
        .ok_or_else(|| SweepError::Internal("the refinement judged no design point".into()))?;

    let verify_points = verify_grid(map.for_all(), file.search.verify).map_err(config)?;
    let rows = runner.run("verify", verify_points.iter().map(|p| (&best.design, p)))?;
    let verification = check(map.limits(), &verify_points, &rows).map_err(internal)?;
    let verify_runs = runner.made - search_runs;
    let runs = runner.batches;
    Ok(DesignResult {
        file,
        map,
        best,
        verify_points,
        verification,
        runs,
        search_runs,
        verify_runs,
        batches,
        threads,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

fn internal(e: crate::DesignError) -> SweepError {
    SweepError::Internal(e.to_string())
}

/// The axis columns of `runs.parquet`: the stage, the design keys, the `for_all` keys.
pub fn runs_axes(file: &DesignFile) -> Vec<SweepAxis> {
    let stage = SweepAxis {
        key: STAGE.into(),
        values: AxisValues::List(vec![Value::String("search".into())]),
        kind: AxisKind::Text,
    };
    std::iter::once(stage)
        .chain(file.design.iter().cloned())
        .chain(file.for_all.iter().cloned())
        .collect()
}

/// Runs batches through the engine and keeps their rows.
struct Runner<'a> {
    file: &'a DesignFile,
    pool: &'a rayon::ThreadPool,
    sim: &'a Model,
    hooks: &'a Hooks<'a>,
    /// Column of each limited metric in a summary's cells.
    metric_cells: Vec<usize>,
    schema: TableSchema,
    batches: Vec<RecordBatch>,
    made: usize,
}

impl<'a> Runner<'a> {
    fn new(
        file: &'a DesignFile,
        map: &Refinement,
        pool: &'a rayon::ThreadPool,
        sim: &'a Model,
        hooks: &'a Hooks<'a>,
    ) -> Runner<'a> {
        let metric_cells = map
            .limits()
            .metrics()
            .iter()
            .map(|m| {
                Summary::COLUMNS
                    .iter()
                    .position(|c| c == m)
                    .expect("the design file checked every metric")
            })
            .collect();
        Runner {
            file,
            pool,
            sim,
            hooks,
            metric_cells,
            schema: TableSchema::new(&runs_axes(file)),
            batches: Vec::new(),
            made: 0,
        }
    }

    /// The scene of one run: the base scene with the design and `for_all` values set.
    fn scene(&self, design: &[f64], for_all: &[f64]) -> Result<(Scene, Vec<Value>), SweepError> {
        let mut scene = self.file.base.clone();
        let mut values = Vec::with_capacity(design.len() + for_all.len());
        for (axes, point) in [(&self.file.design, design), (&self.file.for_all, for_all)] {
            for (a, &x) in axes.iter().zip(point) {
                let v = scene_value(a, x);
                scene
                    .set(&a.key, &v)
                    .map_err(|e| SweepError::Internal(format!("{} = {v}: {e}", a.key)))?;
                values.push(v);
            }
        }
        Ok((scene, values))
    }

    /// One batch: its rows of metric values, in the batch's order.
    fn run<'p>(
        &mut self,
        stage: &str,
        runs: impl Iterator<Item = (&'p Point, &'p Point)>,
    ) -> Result<Vec<Vec<f64>>, SweepError> {
        let mut scenes = Vec::new();
        let mut points = Vec::new();
        for (d, f) in runs {
            let (scene, mut values) = self.scene(d, f)?;
            values.insert(0, Value::String(stage.into()));
            scenes.push(scene);
            points.push(values);
        }
        let done = self.made as u64;
        let count = RunCount::new(done, done + scenes.len() as u64);
        let summaries = compute_scenes(&scenes, self.pool, self.sim, self.hooks, &count)?;
        let mut table = RowsBuilder::new(&self.schema);
        let mut rows = Vec::with_capacity(summaries.len());
        for (i, (s, p)) in summaries.iter().zip(&points).enumerate() {
            table.push((self.made + i) as u64, p, s);
            rows.push(self.metrics(s));
        }
        self.made += summaries.len();
        self.batches.push(table.finish());
        Ok(rows)
    }

    /// A run's row of limited metrics; all `NaN` unless its status is `ok`.
    fn metrics(&self, s: &Summary) -> Vec<f64> {
        if s.status != RunStatus::Ok {
            return vec![f64::NAN; self.metric_cells.len()];
        }
        let cells = s.cells();
        self.metric_cells
            .iter()
            .map(|&c| match cells[c] {
                Cell::Float(Some(v)) => v,
                Cell::Int(n) => n as f64,
                _ => f64::NAN,
            })
            .collect()
    }
}

impl DesignResult {
    /// The design points as one record batch: the columns of `design.parquet`.
    pub fn points_table(&self) -> RecordBatch {
        crate::tables::design_table(self)
    }

    /// The Arrow schema of [`DesignResult::runs`] (that of `runs.parquet`).
    pub fn runs_schema(&self) -> arrow_schema::SchemaRef {
        TableSchema::new(&runs_axes(&self.file)).arrow
    }

    /// `answer.json` as a JSON value.
    pub fn answer(&self) -> serde_json::Value {
        crate::tables::answer_json(self)
    }

    /// The real point of the search for design values given as the file gives them (one per
    /// `[[design]]` key, in order: a number along a range, one of the listed values along a
    /// list); an error names the key and what is allowed.
    pub fn design_point(&self, values: &[Value]) -> Result<Point, SweepError> {
        let axes = &self.file.design;
        if values.len() != axes.len() {
            return Err(SweepError::Config(format!(
                "design point: {} values, expected one per design key ({})",
                values.len(),
                axes.iter()
                    .map(|a| a.key.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        let number = |v: &Value| match v {
            Value::Float(f) => Some(*f),
            Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        axes.iter()
            .zip(values)
            .map(|(a, v)| match &a.values {
                AxisValues::Range { low, high, .. } => number(v)
                    .filter(|x| *x >= *low && *x <= *high)
                    .ok_or_else(|| {
                        SweepError::Config(format!("{} = {v}: a number in [{low}, {high}]", a.key))
                    }),
                AxisValues::List(list) => list
                    .iter()
                    .position(|w| w == v || (number(w).is_some() && number(w) == number(v)))
                    .map(|i| i as f64)
                    .ok_or_else(|| {
                        SweepError::Config(format!(
                            "{} = {v}: one of {}",
                            a.key,
                            list.iter()
                                .map(|w| w.to_string())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ))
                    }),
            })
            .collect()
    }

    /// The refined map's margin at a design point (see [`Refinement::map_margin`]).
    pub fn map_margin(&self, values: &[Value]) -> Result<f64, SweepError> {
        let p = self.design_point(values)?;
        self.map.map_margin(&p).map_err(internal)
    }

    /// Whether a design point is feasible by the refined map (see [`Refinement::classify`]).
    pub fn classify(&self, values: &[Value]) -> Result<bool, SweepError> {
        Ok(self.map_margin(values)? >= 0.0)
    }
}
