//! One run's trajectory and event log as MCAP, for Foxglove (and the `mcap` readers).
//!
//! Layout, per run, under a topic prefix (`""` for a single run, `/run/17` in a sweep):
//!
//! - `{prefix}/state`: one message per trajectory point, schema `cushion.State`. Fields are the
//!   trajectory columns ([`TrajectoryPoint::COLUMNS`]: `t, x_r, v_r, x_t, v_t, x_p, v_p, s, p1,
//!   F_c, F_r`), SI units. A quantity the scene does not have (no object, no gas) is left out of
//!   the message rather than written as `null`, so plots show no line for it.
//! - `{prefix}/events`: one message per event, schema `cushion.Event`: `t`, `name`
//!   (`sensor`, `brake`, `object_contact_begin`, ...), and `point`, the state at that instant.
//!
//! Messages are JSON (`message_encoding = "json"`) described by a `jsonschema` schema.
//! `log_time` and `publish_time` are the simulated time in nanoseconds (`round(t * 1e9)`), so
//! Foxglove's timeline is simulated time from 0.
//!
//! Chunks are not compressed (the crate is built without zstd/lz4); the files stay readable by
//! every MCAP reader.
//!
//! `mcap_read.rs` reads a run back, bit for bit.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};
use std::path::Path;

use cushion_model::{EventLogEntry, Trajectory, TrajectoryPoint};
use mcap::records::MessageHeader;
use mcap::{McapError, McapResult, WriteOptions, Writer};

use crate::trajectory_csv::{push_number, write_atomically};

/// Schema name of `/state` messages.
pub const STATE_SCHEMA_NAME: &str = "cushion.State";
/// Schema name of `/events` messages.
pub const EVENT_SCHEMA_NAME: &str = "cushion.Event";

/// Units of the trajectory columns, in the order of [`TrajectoryPoint::COLUMNS`].
const UNITS: [&str; 11] = ["s", "m", "m/s", "m", "m/s", "m", "m/s", "m", "Pa", "N", "N"];
const DESCRIPTIONS: [&str; 11] = [
    "simulated time",
    "robot flange position",
    "robot flange velocity",
    "tool position",
    "tool velocity",
    "object position",
    "object velocity",
    "stroke x_r - x_t (0 = forward stop)",
    "gas pressure",
    "tool-object contact force (pushes the object along +x)",
    "force of the module on the robot flange",
];

/// The topics of one run under `prefix` (`""` -> `/state`, `/run/17` -> `/run/17/state`).
pub fn topics(prefix: &str) -> (String, String) {
    let p = prefix.trim_end_matches('/');
    (format!("{p}/state"), format!("{p}/events"))
}

/// The JSON schema (draft 2020-12 style object schema) of one state message.
pub fn state_schema() -> String {
    format!(
        r#"{{"title":"{STATE_SCHEMA_NAME}","description":"cushion trajectory point (SI units; absent quantities are omitted)","type":"object","properties":{}}}"#,
        point_properties()
    )
}

/// The JSON schema of one event message.
pub fn event_schema() -> String {
    format!(
        r#"{{"title":"{EVENT_SCHEMA_NAME}","description":"cushion event (sensor, brake, contact begin/end, ...)","type":"object","properties":{{"t":{{"type":"number","description":"simulated time [s]"}},"name":{{"type":"string","description":"event name"}},"point":{{"type":"object","description":"state at the event","properties":{}}}}},"required":["t","name","point"]}}"#,
        point_properties()
    )
}

fn point_properties() -> String {
    let mut s = String::from("{");
    for (i, name) in TrajectoryPoint::COLUMNS.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        s.push_str(&format!(
            r#""{name}":{{"type":"number","description":"{} [{}]"}}"#,
            DESCRIPTIONS[i], UNITS[i]
        ));
    }
    s.push('}');
    s
}

/// A trajectory point as a JSON object (non-finite values left out).
pub fn point_json(p: &TrajectoryPoint) -> String {
    let mut s = String::with_capacity(256);
    push_point_json(&mut s, p);
    s
}

fn push_point_json(s: &mut String, p: &TrajectoryPoint) {
    s.push('{');
    let mut first = true;
    for (name, v) in TrajectoryPoint::COLUMNS.iter().zip(p.values()) {
        if !v.is_finite() {
            continue;
        }
        if !first {
            s.push(',');
        }
        first = false;
        s.push('"');
        s.push_str(name);
        s.push_str("\":");
        // Rust's shortest round-trip float text is valid JSON for finite numbers.
        push_number(s, v);
    }
    s.push('}');
}

fn event_json(e: &EventLogEntry) -> String {
    let mut s = String::with_capacity(300);
    s.push_str("{\"t\":");
    if e.t.is_finite() {
        push_number(&mut s, e.t);
    } else {
        s.push_str("null");
    }
    s.push_str(",\"name\":");
    s.push_str(&serde_json::to_string(&e.name).unwrap_or_else(|_| "\"?\"".to_string()));
    s.push_str(",\"point\":");
    push_point_json(&mut s, &e.point);
    s.push('}');
    s
}

/// Simulated time in s -> nanoseconds (negative or non-finite times clamp to 0).
pub fn time_ns(t: f64) -> u64 {
    if t.is_finite() && t > 0.0 {
        (t * 1e9).round() as u64
    } else {
        0
    }
}

/// The writer options used for cushion files (uncompressed chunks, `cushion` library tag).
pub fn write_options() -> WriteOptions {
    WriteOptions::new()
        .compression(None)
        .library(format!("cushion {}", env!("CARGO_PKG_VERSION")))
}

/// Write one run's `/state` and `/events` channels under `prefix` into an open writer.
/// Schemas are shared between runs (the writer coalesces identical schemas). The caller
/// finishes the writer.
pub fn write_run<W: Write + Seek>(
    writer: &mut Writer<W>,
    prefix: &str,
    trajectory: &Trajectory,
    events: &[EventLogEntry],
) -> McapResult<()> {
    let (state_topic, events_topic) = topics(prefix);
    let state_schema =
        writer.add_schema(STATE_SCHEMA_NAME, "jsonschema", state_schema().as_bytes())?;
    let event_schema =
        writer.add_schema(EVENT_SCHEMA_NAME, "jsonschema", event_schema().as_bytes())?;
    let meta = BTreeMap::new();
    let state_ch = writer.add_channel(state_schema, &state_topic, "json", &meta)?;
    let events_ch = writer.add_channel(event_schema, &events_topic, "json", &meta)?;

    let mut data = String::with_capacity(256);
    for (seq, p) in trajectory.points.iter().enumerate() {
        data.clear();
        push_point_json(&mut data, p);
        let t = time_ns(p.t);
        let header = MessageHeader {
            channel_id: state_ch,
            sequence: seq as u32,
            log_time: t,
            publish_time: t,
        };
        writer.write_to_known_channel(&header, data.as_bytes())?;
    }
    for (seq, e) in events.iter().enumerate() {
        let t = time_ns(e.t);
        let header = MessageHeader {
            channel_id: events_ch,
            sequence: seq as u32,
            log_time: t,
            publish_time: t,
        };
        writer.write_to_known_channel(&header, event_json(e).as_bytes())?;
    }
    Ok(())
}

/// Write a single-run MCAP file (topics `/state` and `/events`), atomically.
pub fn write_mcap(
    path: &Path,
    trajectory: &Trajectory,
    events: &[EventLogEntry],
) -> io::Result<()> {
    write_atomically(path, |w: &mut BufWriter<File>| {
        let mut writer = write_options().create(&mut *w).map_err(mcap_io)?;
        write_run(&mut writer, "", trajectory, events).map_err(mcap_io)?;
        writer.finish().map_err(mcap_io)?;
        Ok(())
    })
}

fn mcap_io(e: McapError) -> io::Error {
    match e {
        McapError::Io(e) => e,
        other => io::Error::other(other),
    }
}

#[cfg(test)]
mod tests;
