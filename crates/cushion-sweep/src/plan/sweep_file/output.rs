//! The `[output]` table: `chunk_size`, `invalid_runs`, `sample_interval`, and `record`, which
//! is checked once the number of runs is known.

use std::collections::BTreeSet;

use toml::Value;

use super::toml_helpers::{as_number, check_keys};
use super::{InvalidRuns, Record, DEFAULT_CHUNK_SIZE};

/// A checked `[output]` table, but for `record`, left as written.
pub(super) struct Output<'a> {
    pub record: Option<&'a Value>,
    pub chunk_size: usize,
    pub invalid_runs: InvalidRuns,
    pub sample_interval: Option<f64>,
}

pub(super) fn parse_output(doc: &toml::Table) -> Result<Output<'_>, String> {
    let table = match doc.get("output") {
        None => None,
        Some(Value::Table(t)) => Some(t),
        Some(_) => return Err("`output` must be a table [output]".to_string()),
    };
    let empty = toml::Table::new();
    let output = table.unwrap_or(&empty);
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
    Ok(Output {
        record: table.and_then(|t| t.get("record")),
        chunk_size,
        invalid_runs,
        sample_interval,
    })
}

/// `record`: `"none"` (default), `"all"` or a list of run numbers below `n_runs`.
pub(super) fn parse_record(record: Option<&Value>, n_runs: u64) -> Result<Record, String> {
    match record {
        None => Ok(Record::None),
        Some(Value::String(s)) if s == "none" => Ok(Record::None),
        Some(Value::String(s)) if s == "all" => Ok(Record::All),
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
            Ok(Record::Runs(runs))
        }
        Some(other) => Err(format!(
            "[output] record = {other}: allowed \"none\", \"all\" or a list of run numbers"
        )),
    }
}
