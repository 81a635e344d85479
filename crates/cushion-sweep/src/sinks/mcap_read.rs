//! A recorded run read back from MCAP ([`read_run`]), bit for bit: the writer
//! (`trajectory_mcap.rs`) prints each number as Rust's shortest text that parses back to the
//! same `f64`, and `serde_json`, built with its `float_roundtrip` feature, parses it correctly
//! rounded. [`recorded_runs`] lists the runs of a sweep's file.

use std::collections::BTreeSet;

use cushion_model::{EventLogEntry, Trajectory, TrajectoryPoint};
use mcap::{McapError, MessageStream};
use serde_json::Value;
use thiserror::Error;

use crate::trajectory_mcap::topics;

/// Why a recorded run could not be read back.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ReadError {
    /// The bytes are not a readable MCAP file (the `mcap` crate's message).
    #[error("not a readable MCAP file: {0}")]
    NotMcap(String),
    /// The file holds no such run (`None`: no single run, `/state`, and not exactly one
    /// `/run/<n>`).
    #[error("{}", no_such_run_message(*.run, .available))]
    NoSuchRun {
        run: Option<u64>,
        available: Vec<u64>,
    },
    /// A message of the run is not what the writer writes.
    #[error("bad message on `{topic}`: {message}")]
    BadMessage { topic: String, message: String },
}

fn no_such_run_message(run: Option<u64>, available: &[u64]) -> String {
    let wanted = match run {
        Some(n) => format!("no run {n} (topics /run/{n}/state, /run/{n}/events) in the file"),
        None => "no single run (topics /state, /events) in the file".to_string(),
    };
    let holds = match available {
        [] => "it holds no /run/<n> runs".to_string(),
        [n] => format!("it holds run {n}"),
        _ => format!(
            "it holds runs {}",
            available
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    format!("{wanted}; {holds}")
}

fn not_mcap(e: McapError) -> ReadError {
    ReadError::NotMcap(e.to_string())
}

/// The topics of the file's channels: from its summary section when it has one (channels
/// without messages included), else from its messages.
fn channel_topics(bytes: &[u8]) -> Result<BTreeSet<String>, ReadError> {
    if let Some(summary) = mcap::Summary::read(bytes).map_err(not_mcap)? {
        return Ok(summary.channels.values().map(|c| c.topic.clone()).collect());
    }
    let mut topics = BTreeSet::new();
    for m in MessageStream::new(bytes).map_err(not_mcap)? {
        topics.insert(m.map_err(not_mcap)?.channel.topic.clone());
    }
    Ok(topics)
}

/// The run number of a `/run/<n>/state` or `/run/<n>/events` topic.
fn run_of_topic(topic: &str) -> Option<u64> {
    let rest = topic.strip_prefix("/run/")?;
    let (n, leaf) = rest.split_once('/')?;
    if !(leaf == "state" || leaf == "events")
        || n.is_empty()
        || !n.bytes().all(|b| b.is_ascii_digit())
    {
        return None;
    }
    n.parse().ok()
}

fn runs_in(topics: &BTreeSet<String>) -> Vec<u64> {
    let runs: BTreeSet<u64> = topics.iter().filter_map(|t| run_of_topic(t)).collect();
    runs.into_iter().collect()
}

/// The run numbers `n` of the `/run/<n>/...` topics in an MCAP file (a sweep's), ascending.
pub fn recorded_runs(bytes: &[u8]) -> Result<Vec<u64>, ReadError> {
    Ok(runs_in(&channel_topics(bytes)?))
}

/// Read one run's trajectory and event log back from an MCAP file written by [`write_run`].
///
/// `run = None` reads `/state` and `/events` (a file of `cushion simulate --mcap`), or, when the
/// file has neither, its only `/run/<n>` run; `Some(n)` reads `/run/<n>/state` and
/// `/run/<n>/events`. Points and events come in the order they were written; a quantity left out
/// of a message (the scene does not have it) is NaN, as in [`Trajectory`]. Every number is the
/// `f64` that was written, to the bit.
pub fn read_run(
    bytes: &[u8],
    run: Option<u64>,
) -> Result<(Trajectory, Vec<EventLogEntry>), ReadError> {
    let channels = channel_topics(bytes)?;
    let has = |prefix: &str| {
        let (state, events) = topics(prefix);
        channels.contains(&state) || channels.contains(&events)
    };
    let runs = runs_in(&channels);
    let no_such_run = || ReadError::NoSuchRun {
        run,
        available: runs.clone(),
    };
    let prefix = match run {
        Some(n) => {
            let p = format!("/run/{n}");
            if !has(&p) {
                return Err(no_such_run());
            }
            p
        }
        None if has("") => String::new(),
        None => match runs.as_slice() {
            [n] => format!("/run/{n}"),
            _ => return Err(no_such_run()),
        },
    };
    let (state_topic, events_topic) = topics(&prefix);

    let mut trajectory = Trajectory::default();
    let mut events = Vec::new();
    for m in MessageStream::new(bytes).map_err(not_mcap)? {
        let m = m.map_err(not_mcap)?;
        let topic = &m.channel.topic;
        let is_state = *topic == state_topic;
        if !is_state && *topic != events_topic {
            continue;
        }
        let bad = |message: String| ReadError::BadMessage {
            topic: topic.clone(),
            message,
        };
        if m.channel.message_encoding != "json" {
            return Err(bad(format!(
                "message encoding `{}`, expected `json`",
                m.channel.message_encoding
            )));
        }
        let text = std::str::from_utf8(&m.data).map_err(|e| bad(format!("not UTF-8 text: {e}")))?;
        let value: Value =
            serde_json::from_str(text).map_err(|e| bad(format!("invalid JSON: {e}")))?;
        if is_state {
            trajectory
                .points
                .push(point_from_json(&value).map_err(bad)?);
        } else {
            events.push(event_from_json(&value).map_err(bad)?);
        }
    }
    Ok((trajectory, events))
}

/// What a JSON value is, for messages.
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// A JSON number or null (NaN: a quantity the scene lacks, or a non-finite time).
fn number(name: &str, v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => n
            .as_f64()
            .ok_or_else(|| format!("`{name}` = {n}: not an f64")),
        Value::Null => Ok(f64::NAN),
        other => Err(format!("`{name}` is {}, expected a number", kind(other))),
    }
}

fn point_from_json(value: &Value) -> Result<TrajectoryPoint, String> {
    let Value::Object(fields) = value else {
        return Err(format!("expected a JSON object, found {}", kind(value)));
    };
    let mut v = [f64::NAN; 11];
    for (name, x) in fields {
        // fields of other writers' messages that are no trajectory column are no concern here
        if let Some(i) = TrajectoryPoint::COLUMNS.iter().position(|c| c == name) {
            v[i] = number(name, x)?;
        }
    }
    let [t, x_r, v_r, x_t, v_t, x_p, v_p, s, p1, f_c, f_r] = v;
    Ok(TrajectoryPoint {
        t,
        x_r,
        v_r,
        x_t,
        v_t,
        x_p,
        v_p,
        s,
        p1,
        f_c,
        f_r,
    })
}

fn event_from_json(value: &Value) -> Result<EventLogEntry, String> {
    let Value::Object(fields) = value else {
        return Err(format!("expected a JSON object, found {}", kind(value)));
    };
    let field = |key: &str| fields.get(key).ok_or_else(|| format!("no `{key}` field"));
    let t = number("t", field("t")?)?;
    let name = match field("name")? {
        Value::String(s) => s.clone(),
        other => return Err(format!("`name` is {}, expected a string", kind(other))),
    };
    let point = point_from_json(field("point")?).map_err(|e| format!("`point`: {e}"))?;
    Ok(EventLogEntry { t, name, point })
}
