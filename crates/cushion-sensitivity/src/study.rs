//! A study: the analysis of a run summary's columns, as `cushion sensitivity` and
//! `cushion.sensitivity` do it. Engine-free: the summary (Arrow record batches with a `run`
//! column, a `status` column, one column per input and the outputs) comes from whoever ran the
//! sample; this module picks the outputs, deals with the runs that did not end `ok`, calls
//! [`analyze`], and lays the answer out as a long table (written as Parquet and CSV; the chart
//! is in [`crate::chart`]).
//!
//! The long table has one row per index: `output`, `input` (for `S1` and `ST`), `input_1` and
//! `input_2` (for `S2`), `index` (`S1`, `ST`, `S2`; `constant` for an output that takes one
//! value on every run, `value` being that value; `not_finite` for an output missing or not
//! finite on some runs, `value` being how many), `value` and `conf` (the half-width of the
//! interval; empty for `constant` and `not_finite`).

use std::time::Instant;

use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Schema};

use crate::error::{config, SensitivityError};
use crate::saltelli::SaltelliSample;
use crate::sobol::{analyze, Sensitivity, SobolOptions};

pub use crate::long_table::{
    csv_text, long_schema, long_table, parquet_bytes, write_study, STUDY_FILES,
};
pub use crate::study_options::{OnFailed, StudyOptions, STUDY_KEYS};

/// The numeric columns of a summary (floats, integers, booleans as 0/1) that are outputs: all
/// but `run` and the inputs.
pub fn numeric_outputs(schema: &Schema, inputs: &[String]) -> Vec<String> {
    schema
        .fields()
        .iter()
        .filter(|f| {
            matches!(
                f.data_type(),
                DataType::Float64 | DataType::Int64 | DataType::Boolean
            )
        })
        .map(|f| f.name().clone())
        .filter(|n| n != "run" && !inputs.contains(n))
        .collect()
}

/// The outputs to analyse: `requested` (each checked against the summary's numeric outputs), or
/// every numeric output.
pub fn resolve_outputs(
    schema: &Schema,
    inputs: &[String],
    requested: Option<&[String]>,
) -> Result<Vec<String>, SensitivityError> {
    let all = numeric_outputs(schema, inputs);
    let Some(req) = requested else {
        return Ok(all);
    };
    for (i, name) in req.iter().enumerate() {
        if !all.contains(name) {
            return Err(config(
                "[sensitivity] outputs",
                format!("{name:?}"),
                format!("not a numeric summary field (allowed: {})", all.join(", ")),
            ));
        }
        if req[..i].contains(name) {
            return Err(config(
                "[sensitivity] outputs",
                format!("{name:?}"),
                "listed twice",
            ));
        }
    }
    Ok(req.to_vec())
}

/// What the study says of one output.
#[derive(Clone, Debug, PartialEq)]
pub enum Finding {
    /// The estimator's answer (indices, or a constant output).
    Sensitivity(Sensitivity),
    /// The output is missing or not finite on this many of the analysed runs: no index.
    NotFinite { runs: usize },
}

/// A finished study.
#[derive(Clone, Debug)]
pub struct Study {
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    /// One per output, in order.
    pub findings: Vec<Finding>,
    pub second_order: bool,
    pub conf_level: f64,
    /// Base points in the sample, and those analysed (fewer when some were dropped).
    pub base_points: usize,
    pub base_points_used: usize,
    /// Runs that did not end `ok`.
    pub failed_runs: usize,
    /// Seconds spent gathering the columns and estimating (not running the sample).
    pub analysis_seconds: f64,
}

impl Study {
    /// Base points dropped for holding a failed run.
    pub fn dropped_base_points(&self) -> usize {
        self.base_points - self.base_points_used
    }
}

fn column<'a>(batch: &'a RecordBatch, name: &str) -> Result<&'a ArrayRef, SensitivityError> {
    batch.column_by_name(name).ok_or_else(|| {
        config(
            "summary",
            format!("no column `{name}`"),
            "a run summary has it",
        )
    })
}

/// The values of a numeric column as floats (booleans as 0 and 1, a missing value NaN).
fn floats(a: &ArrayRef, out: &mut Vec<f64>) {
    if let Some(f) = a.as_any().downcast_ref::<Float64Array>() {
        out.extend((0..f.len()).map(|i| if f.is_null(i) { f64::NAN } else { f.value(i) }));
    } else if let Some(n) = a.as_any().downcast_ref::<Int64Array>() {
        out.extend((0..n.len()).map(|i| {
            if n.is_null(i) {
                f64::NAN
            } else {
                n.value(i) as f64
            }
        }));
    } else if let Some(b) = a.as_any().downcast_ref::<BooleanArray>() {
        out.extend((0..b.len()).map(|i| {
            if b.is_null(i) {
                f64::NAN
            } else if b.value(i) {
                1.0
            } else {
                0.0
            }
        }));
    } else {
        out.extend(std::iter::repeat_n(f64::NAN, a.len()));
    }
}

/// A numeric column over every batch, as floats.
fn gather(batches: &[RecordBatch], name: &str) -> Result<Vec<f64>, SensitivityError> {
    let mut out = Vec::new();
    for b in batches {
        floats(column(b, name)?, &mut out);
    }
    Ok(out)
}

/// How many failed runs a message lists by their inputs.
const LIST_FAILED: usize = 5;

/// Analyse the outputs of a Saltelli sample: `batches` hold its summary, one row per run in run
/// order (`run` 0, 1, ..); `inputs` name its input columns in the sample's order. Runs on the
/// current rayon pool; the answer does not depend on the thread count.
pub fn run_study(
    batches: &[RecordBatch],
    inputs: &[String],
    sample: &SaltelliSample,
    outputs: &[String],
    opts: &StudyOptions,
) -> Result<Study, SensitivityError> {
    let n_rows = check_rows(batches, sample)?;
    let status = statuses(batches)?;
    let failed: Vec<usize> = (0..n_rows)
        .filter(|&i| status[i].as_deref() != Some("ok"))
        .collect();
    let used = base_points_to_use(batches, inputs, sample, &status, &failed, opts)?;
    let started = Instant::now();
    let findings = findings(batches, sample, outputs, &used, opts)?;
    Ok(Study {
        inputs: inputs.to_vec(),
        outputs: outputs.to_vec(),
        findings,
        second_order: sample.second_order(),
        conf_level: opts.conf_level,
        base_points: sample.n_base(),
        base_points_used: used.len(),
        failed_runs: failed.len(),
        analysis_seconds: started.elapsed().as_secs_f64(),
    })
}

/// The summary holds the sample's runs, in order: their count.
fn check_rows(batches: &[RecordBatch], sample: &SaltelliSample) -> Result<usize, SensitivityError> {
    let n_rows: usize = batches.iter().map(|b| b.num_rows()).sum();
    if n_rows as u64 != sample.n_rows() {
        return Err(config(
            "summary",
            format!("{n_rows} rows"),
            format!("the saltelli sample has {} runs", sample.n_rows()),
        ));
    }
    let runs = gather(batches, "run")?;
    if let Some(i) = runs.iter().enumerate().position(|(i, r)| *r != i as f64) {
        return Err(config(
            "summary",
            format!("row {i} holds run {}", runs[i]),
            "the rows must be the runs in order (a whole sweep, not a shard)",
        ));
    }
    Ok(n_rows)
}

/// Every run's `status`.
fn statuses(batches: &[RecordBatch]) -> Result<Vec<Option<String>>, SensitivityError> {
    let mut status = Vec::new();
    for b in batches {
        let a = column(b, "status")?;
        let s = a
            .as_any()
            .downcast_ref::<StringArray>()
            .ok_or_else(|| config("summary", "column `status`", "must be text"))?;
        status.extend(s.iter().map(|x| x.map(str::to_string)));
    }
    Ok(status)
}

/// The base points to analyse: all, unless runs `failed`; then, by `on_failed`, an error that
/// lists the first of them with their inputs, or the base points that hold none.
fn base_points_to_use(
    batches: &[RecordBatch],
    inputs: &[String],
    sample: &SaltelliSample,
    status: &[Option<String>],
    failed: &[usize],
    opts: &StudyOptions,
) -> Result<Vec<usize>, SensitivityError> {
    let n_rows = status.len();
    let mut keep = vec![true; sample.n_base()];
    if !failed.is_empty() {
        match opts.on_failed {
            OnFailed::Stop => {
                let input_cols: Vec<Vec<f64>> = inputs
                    .iter()
                    .map(|k| gather(batches, k))
                    .collect::<Result<_, _>>()?;
                let listed: Vec<String> = failed
                    .iter()
                    .take(LIST_FAILED)
                    .map(|&r| {
                        let point: Vec<String> = inputs
                            .iter()
                            .zip(&input_cols)
                            .map(|(k, c)| format!("{k} = {}", c[r]))
                            .collect();
                        format!(
                            "run {r} ({}): {}",
                            point.join(", "),
                            status[r].as_deref().unwrap_or("no status")
                        )
                    })
                    .collect();
                return Err(SensitivityError::FailedRuns(format!(
                    "{} of {n_rows} runs did not end ok, so no index would be honest: {}{}. Set [sensitivity] on_failed = \"drop_base_point\" to analyse without their base points",
                    failed.len(),
                    listed.join("; "),
                    if failed.len() > LIST_FAILED { "; ..." } else { "" }
                )));
            }
            OnFailed::DropBasePoint => {
                for &r in failed {
                    keep[r / sample.block()] = false;
                }
            }
        }
    }
    let used: Vec<usize> = (0..sample.n_base()).filter(|&i| keep[i]).collect();
    if used.is_empty() {
        return Err(SensitivityError::FailedRuns(format!(
            "{} of {n_rows} runs did not end ok, and every base point holds one: nothing is left to analyse",
            failed.len()
        )));
    }
    Ok(used)
}

/// What the study says of each output, over the `used` base points' blocks.
fn findings(
    batches: &[RecordBatch],
    sample: &SaltelliSample,
    outputs: &[String],
    used: &[usize],
    opts: &StudyOptions,
) -> Result<Vec<Finding>, SensitivityError> {
    let block = sample.block();
    let mut findings: Vec<Option<Finding>> = vec![None; outputs.len()];
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut analysed: Vec<usize> = Vec::new();
    for (o, name) in outputs.iter().enumerate() {
        let all = gather(batches, name)?;
        let mut kept = Vec::with_capacity(used.len() * block);
        for &i in used {
            kept.extend_from_slice(&all[i * block..(i + 1) * block]);
        }
        let bad = kept.iter().filter(|x| !x.is_finite()).count();
        if bad > 0 {
            findings[o] = Some(Finding::NotFinite { runs: bad });
        } else {
            columns.push(kept);
            analysed.push(o);
        }
    }
    let refs: Vec<&[f64]> = columns.iter().map(|c| c.as_slice()).collect();
    let sobol = SobolOptions {
        second_order: sample.second_order(),
        resamples: opts.resamples,
        conf_level: opts.conf_level,
        seed: opts.seed,
    };
    let results = analyze(sample.n_inputs(), &refs, &sobol).map_err(|e| match e {
        SensitivityError::Output { output, problem } => SensitivityError::Output {
            output: analysed[output],
            problem: format!("{}: {problem}", outputs[analysed[output]]),
        },
        other => other,
    })?;
    for (o, r) in analysed.into_iter().zip(results) {
        findings[o] = Some(Finding::Sensitivity(r));
    }
    Ok(findings
        .into_iter()
        .map(|f| f.expect("every output has a finding"))
        .collect())
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use arrow_schema::Field;

    use super::*;

    /// A summary of the 2-input, 8-base-point sample (no second order: 32 rows) with the output
    /// `y = a + 2 b²`, and `status` not ok on the rows in `failed`.
    fn summary(sample: &SaltelliSample, failed: &[usize]) -> (RecordBatch, Vec<f64>) {
        let n = sample.n_rows() as usize;
        let pts: Vec<Vec<f64>> = (0..n as u64).map(|r| sample.unit_point(r)).collect();
        let y: Vec<f64> = pts.iter().map(|p| p[0] + 2.0 * p[1] * p[1]).collect();
        let status: Vec<&str> = (0..n)
            .map(|r| {
                if failed.contains(&r) {
                    "max_steps"
                } else {
                    "ok"
                }
            })
            .collect();
        let schema = Arc::new(Schema::new(vec![
            Field::new("run", DataType::Int64, false),
            Field::new("a", DataType::Float64, false),
            Field::new("b", DataType::Float64, false),
            Field::new("status", DataType::Utf8, false),
            Field::new("y", DataType::Float64, true),
            Field::new("flag", DataType::Boolean, true),
        ]));
        let cols: Vec<ArrayRef> = vec![
            Arc::new(Int64Array::from((0..n as i64).collect::<Vec<_>>())),
            Arc::new(Float64Array::from(
                pts.iter().map(|p| p[0]).collect::<Vec<_>>(),
            )),
            Arc::new(Float64Array::from(
                pts.iter().map(|p| p[1]).collect::<Vec<_>>(),
            )),
            Arc::new(StringArray::from(status)),
            Arc::new(Float64Array::from(y.clone())),
            Arc::new(BooleanArray::from(vec![false; n])),
        ];
        (RecordBatch::try_new(schema, cols).unwrap(), y)
    }

    fn inputs() -> Vec<String> {
        vec!["a".into(), "b".into()]
    }

    #[test]
    fn outputs_are_the_numeric_columns_but_run_and_the_inputs() {
        let s = SaltelliSample::new(2, 8, false, 0).unwrap();
        let (b, _) = summary(&s, &[]);
        assert_eq!(numeric_outputs(&b.schema(), &inputs()), ["y", "flag"]);
        let e = resolve_outputs(&b.schema(), &inputs(), Some(&["z".to_string()])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "[sensitivity] outputs = \"z\": not a numeric summary field (allowed: y, flag)"
        );
    }

    #[test]
    fn failed_runs_stop_or_drop_their_base_points() {
        let s = SaltelliSample::new(2, 8, false, 0).unwrap();
        let (b, y) = summary(&s, &[5, 30]);
        let outputs = vec!["y".to_string(), "flag".to_string()];
        let mut opts = StudyOptions {
            resamples: 20,
            ..StudyOptions::default()
        };
        let e = run_study(std::slice::from_ref(&b), &inputs(), &s, &outputs, &opts).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("2 of 32 runs did not end ok"), "{msg}");
        assert!(
            msg.contains("run 5 (a = ") && msg.contains("): max_steps; run 30 ("),
            "{msg}"
        );

        opts.on_failed = OnFailed::DropBasePoint;
        let st = run_study(std::slice::from_ref(&b), &inputs(), &s, &outputs, &opts).unwrap();
        // Rows 5 and 30 lie in the blocks of base points 1 and 7 (4 rows each).
        assert_eq!(
            (
                st.base_points_used,
                st.dropped_base_points(),
                st.failed_runs
            ),
            (6, 2, 2)
        );
        let kept: Vec<f64> = (0..8)
            .filter(|i| *i != 1 && *i != 7)
            .flat_map(|i| y[i * 4..(i + 1) * 4].to_vec())
            .collect();
        let sobol = SobolOptions {
            second_order: false,
            resamples: 20,
            conf_level: 0.95,
            seed: 0,
        };
        let want = analyze(2, &[&kept], &sobol).unwrap();
        assert_eq!(st.findings[0], Finding::Sensitivity(want[0].clone()));
        assert_eq!(
            st.findings[1],
            Finding::Sensitivity(Sensitivity::Constant { value: 0.0 })
        );
        let t = long_table(&st);
        // y: S1 and ST of a and b; flag: one constant row.
        assert_eq!(t.num_rows(), 5);
        let csv = csv_text(&t);
        assert!(csv.ends_with("flag,,,,constant,0,\n"), "{csv}");
    }

    #[test]
    fn the_sensitivity_table_is_checked() {
        let t: toml::Table = "outputs = [\"y\"]\nresamples = 50\nconf_level = 0.9\nseed = 4\non_failed = \"drop_base_point\"\n".parse().unwrap();
        let o = StudyOptions::from_table(Some(&t)).unwrap();
        assert_eq!(
            o,
            StudyOptions {
                outputs: Some(vec!["y".into()]),
                resamples: 50,
                conf_level: 0.9,
                seed: 4,
                on_failed: OnFailed::DropBasePoint
            }
        );
        for (text, want) in [
            (
                "outputs = []",
                "[sensitivity] outputs = []: must be a non-empty list",
            ),
            (
                "resamples = 1",
                "[sensitivity] resamples = 1: must be an integer from 2",
            ),
            (
                "conf_level = 1.0",
                "[sensitivity] conf_level = 1.0: must be a number strictly",
            ),
            (
                "seed = -1",
                "[sensitivity] seed = -1: must be an integer >= 0",
            ),
            (
                "on_failed = \"skip\"",
                "[sensitivity] on_failed = \"skip\": allowed",
            ),
            ("resampels = 3", "[sensitivity] resampels = 3: unknown key"),
        ] {
            let t: toml::Table = text.parse().unwrap();
            let e = StudyOptions::from_table(Some(&t)).unwrap_err().to_string();
            assert!(e.starts_with(want), "{text}: {e}");
        }
    }
}
