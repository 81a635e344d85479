//! The answer of a design question as tables and JSON: the design points (`design.parquet`,
//! `design.csv`) and `answer.json`.
//!
//! `design.parquet`: one row per evaluated design point, in the order the refinement added
//! them: the design keys (the value itself along a list axis: a module's name, a number); per
//! worst case searched for, `<metric>.worst` (the run's own value, signed) and its witness
//! `<metric>.at.<key>` for every `for_all` key (when one metric has two worst cases, a `max` and
//! a `min` limit or an objective the other way, they are `<metric>.max.worst`,
//! `<metric>.max.at.<key>` and `<metric>.min.…`); `objective` (with an objective: the worst
//! case it ranks, its size with `abs`); `feasible`; `margin` (the smallest relative distance of
//! the worst cases to their limits, negative when violated, `-inf` for a failed run); `runs`
//! spent on the point.

use std::sync::Arc;

use arrow_array::builder::{BooleanBuilder, Float64Builder, Int64Builder, StringBuilder};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use cushion_sweep::sweep_file::{Axis as SweepAxis, AxisKind};
use serde_json::{json, Map, Value as Json};
use toml::Value;

use crate::design_file::scene_value;
use crate::engine_runs::DesignResult;
use crate::limits::Limits;
use crate::metrics::{Direction, Worst};
use crate::refine::DesignPoint;

/// The name of each worst case searched for (in the order of [`Limits::targets`]): the metric,
/// with `.max` or `.min` when the metric has two.
pub fn target_names(limits: &Limits) -> Vec<String> {
    let targets = limits.targets();
    targets
        .iter()
        .map(|t| {
            let metric = &limits.metrics()[t.metric];
            if targets.iter().filter(|u| u.metric == t.metric).count() > 1 {
                let end = match t.direction {
                    Direction::Max | Direction::AbsMax => "max",
                    Direction::Min | Direction::AbsMin => "min",
                };
                format!("{metric}.{end}")
            } else {
                metric.clone()
            }
        })
        .collect()
}

/// The name of a direction in `answer.json`.
pub fn direction_name(d: Direction) -> &'static str {
    match d {
        Direction::Max => "max",
        Direction::Min => "min",
        Direction::AbsMax => "abs_max",
        Direction::AbsMin => "abs_min",
    }
}

/// A column of axis values (numbers, strings or booleans, as the axis's kind).
enum ValueColumn {
    Number(Float64Builder),
    Text(StringBuilder),
    Bool(BooleanBuilder),
}

impl ValueColumn {
    fn new(axis: &SweepAxis) -> ValueColumn {
        match axis.kind {
            AxisKind::Number => ValueColumn::Number(Float64Builder::new()),
            AxisKind::Text => ValueColumn::Text(StringBuilder::new()),
            AxisKind::Bool => ValueColumn::Bool(BooleanBuilder::new()),
        }
    }

    fn data_type(axis: &SweepAxis) -> DataType {
        match axis.kind {
            AxisKind::Number => DataType::Float64,
            AxisKind::Text => DataType::Utf8,
            AxisKind::Bool => DataType::Boolean,
        }
    }

    fn push(&mut self, v: &Value) {
        match (self, v) {
            (ValueColumn::Number(b), Value::Float(f)) => b.append_value(*f),
            (ValueColumn::Number(b), Value::Integer(i)) => b.append_value(*i as f64),
            (ValueColumn::Text(b), Value::String(s)) => b.append_value(s),
            (ValueColumn::Bool(b), Value::Boolean(x)) => b.append_value(*x),
            (ValueColumn::Number(b), _) => b.append_null(),
            (ValueColumn::Text(b), other) => b.append_value(other.to_string()),
            (ValueColumn::Bool(b), _) => b.append_null(),
        }
    }

    fn finish(self) -> ArrayRef {
        match self {
            ValueColumn::Number(mut b) => Arc::new(b.finish()),
            ValueColumn::Text(mut b) => Arc::new(b.finish()),
            ValueColumn::Bool(mut b) => Arc::new(b.finish()),
        }
    }
}

/// The design points as one record batch (the columns of `design.parquet`, module docs).
pub fn design_table(r: &DesignResult) -> RecordBatch {
    design_points_table(r, r.map.points())
}

/// Any design points of this question as a batch with `design.parquet`'s columns.
pub fn design_points_table(r: &DesignResult, points: &[DesignPoint]) -> RecordBatch {
    let (design, for_all) = (&r.file.design, &r.file.for_all);
    let limits = r.map.limits();
    let names = target_names(limits);
    let mut fields = Vec::new();
    let mut columns: Vec<ArrayRef> = Vec::new();

    for (i, a) in design.iter().enumerate() {
        let mut c = ValueColumn::new(a);
        for p in points {
            c.push(&scene_value(a, p.design[i]));
        }
        fields.push(Field::new(&a.key, ValueColumn::data_type(a), true));
        columns.push(c.finish());
    }
    for (t, name) in names.iter().enumerate() {
        let mut worst = Float64Builder::new();
        for p in points {
            worst.append_value(p.worst[t].value);
        }
        fields.push(Field::new(format!("{name}.worst"), DataType::Float64, true));
        columns.push(Arc::new(worst.finish()));
        for (k, a) in for_all.iter().enumerate() {
            let mut c = ValueColumn::new(a);
            for p in points {
                c.push(&scene_value(a, p.worst[t].witness[k]));
            }
            fields.push(Field::new(
                format!("{name}.at.{}", a.key),
                ValueColumn::data_type(a),
                true,
            ));
            columns.push(c.finish());
        }
    }
    if limits.objective().is_some() {
        let mut b = Float64Builder::new();
        for p in points {
            b.append_option(p.objective);
        }
        fields.push(Field::new("objective", DataType::Float64, true));
        columns.push(Arc::new(b.finish()));
    }
    let mut feasible = BooleanBuilder::new();
    let mut margin = Float64Builder::new();
    let mut runs = Int64Builder::new();
    for p in points {
        feasible.append_value(p.feasible);
        margin.append_value(p.margin);
        runs.append_value(p.runs as i64);
    }
    fields.push(Field::new("feasible", DataType::Boolean, false));
    columns.push(Arc::new(feasible.finish()));
    fields.push(Field::new("margin", DataType::Float64, false));
    columns.push(Arc::new(margin.finish()));
    fields.push(Field::new("runs", DataType::Int64, false));
    columns.push(Arc::new(runs.finish()));
    RecordBatch::try_new(Arc::new(Schema::new(fields)), columns)
        .expect("columns match the schema by construction")
}

/// A scene value as JSON (a float as its shortest round-trip form, so `--set` gives it back to
/// the bit).
fn value_json(v: &Value) -> Json {
    match v {
        Value::Float(f) => json!(f),
        Value::Integer(i) => json!(i),
        Value::String(s) => json!(s),
        Value::Boolean(b) => json!(b),
        other => json!(other.to_string()),
    }
}

/// A point of a box as `{key: value}`.
fn point_json(axes: &[SweepAxis], point: &[f64]) -> Json {
    let m: Map<String, Json> = axes
        .iter()
        .zip(point)
        .map(|(a, &x)| (a.key.clone(), value_json(&scene_value(a, x))))
        .collect();
    Json::Object(m)
}

/// The worst cases of a design point, one object per worst case searched for.
fn worst_json(r: &DesignResult, worst: &[Worst]) -> Json {
    let limits = r.map.limits();
    let names = target_names(limits);
    let list: Vec<Json> = limits
        .targets()
        .iter()
        .zip(worst)
        .zip(&names)
        .map(|((t, w), name)| {
            let metric = &limits.metrics()[t.metric];
            let limit = r.file.limits.iter().find(|l| &l.metric == metric);
            json!({
                "name": name,
                "metric": metric,
                "direction": direction_name(t.direction),
                "limit": limit.map(|l| json!({"max": l.max, "min": l.min, "abs": l.abs})),
                "value": if w.failed { Json::Null } else { json!(w.value) },
                "failed": w.failed,
                "at": point_json(&r.file.for_all, &w.witness),
            })
        })
        .collect();
    Json::Array(list)
}

/// `answer.json`: the chosen design, its worst cases and witnesses, its margin, the
/// verification, the runs spent in all and the wall time.
pub fn answer_json(r: &DesignResult) -> Json {
    let b = &r.best;
    let v = &r.verification;
    let objective = r.file.objective.as_ref().map(|o| {
        json!({
            "metric": o.metric,
            "sense": match o.sense {
                crate::Sense::Minimize => "minimize",
                crate::Sense::Maximize => "maximize",
            },
            "value": b.objective,
        })
    });
    json!({
        "name": r.file.name,
        "design": point_json(&r.file.design, &b.design),
        "feasible": b.feasible,
        "margin": finite_or_null(b.margin),
        "objective": objective,
        "worst": worst_json(r, &b.worst),
        "runs_at_design": b.runs,
        "verification": {
            "points_per_range": r.file.search.verify,
            "runs": v.runs,
            "all_met": v.all_met,
            "violations": v.violations,
            "failed": v.failed,
            "margin": finite_or_null(v.margin),
            "worst": worst_json(r, &v.worst),
        },
        "design_points": r.map.points().len(),
        "feasible_points": r.map.points().iter().filter(|p| p.feasible).count(),
        "runs": {
            "search": r.search_runs,
            "verify": r.verify_runs,
            "total": r.search_runs + r.verify_runs,
        },
        "batches": r.batches,
        "threads": r.threads,
        "wall_seconds": r.wall_seconds,
        "search": {
            "resolution": r.file.search.resolution,
            "tolerance": r.file.search.tolerance,
            "verify": r.file.search.verify,
        },
    })
}

fn finite_or_null(x: f64) -> Json {
    if x.is_finite() {
        json!(x)
    } else {
        Json::Null
    }
}
