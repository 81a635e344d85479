//! `cushion simulate` run as a user runs it: summary, `--set`, scene files, and the trajectory
//! outputs (`--csv`, `--mcap`, `--plot`) checked against the JSON summary.

use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

fn cushion(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cushion"))
        .arg("simulate")
        .args(args)
        .output()
        .expect("run cushion")
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

/// Run with `--json`, expect status 0 and exactly one JSON object on stdout.
fn json(args: &[&str]) -> Value {
    let mut a = args.to_vec();
    a.push("--json");
    let o = cushion(&a);
    assert_eq!(
        o.status.code(),
        Some(0),
        "args {args:?}\nstdout: {}\nstderr: {}",
        stdout(&o),
        String::from_utf8_lossy(&o.stderr)
    );
    // from_str rejects trailing content: stdout holds exactly one JSON value.
    let v: Value = serde_json::from_str(&stdout(&o)).expect("stdout is one JSON value");
    assert!(v.is_object());
    v
}

fn f(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("`{key}` is not a number: {}", v[key]))
}

/// Relative closeness. JSON read back with serde_json (whose default float parser may be off by
/// an ulp) is compared with `rel = 1e-15`; the files themselves hold shortest round-trip text.
fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

/// CSV trajectory: header and rows (None for empty cells).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|c| {
                    if c.is_empty() {
                        None
                    } else {
                        Some(c.parse::<f64>().unwrap())
                    }
                })
                .collect::<Vec<_>>()
        })
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

const SUMMARY_NAMES: [&str; 16] = [
    "status",
    "message",
    "t_detect",
    "t_brake",
    "peak_robot_force",
    "t_peak_robot_force",
    "robot_impulse",
    "peak_contact_force",
    "object_impacts",
    "object_final_velocity",
    "object_final_momentum",
    "object_travel",
    "max_stroke",
    "back_stop_hit",
    "max_gas_pressure",
    "energy_residual",
];

/// Whether `value` conforms to `schema`, for the part of JSON Schema the MCAP schemas use
/// (`type` object / number / string, `properties`, `required`), and declares every key it has
/// (so a viewer finds each field with its description). The error names the offending path.
fn conforms(value: &Value, schema: &Value, path: &str) -> Result<(), String> {
    match schema["type"].as_str() {
        Some("number") if value.is_number() => Ok(()),
        Some("string") if value.is_string() => Ok(()),
        Some("object") => {
            let obj = value
                .as_object()
                .ok_or_else(|| format!("{path}: not an object"))?;
            for key in schema["required"].as_array().into_iter().flatten() {
                let key = key.as_str().unwrap_or_default();
                if !obj.contains_key(key) {
                    return Err(format!("{path}: lacks the required {key}"));
                }
            }
            for (key, v) in obj {
                let sub = schema["properties"]
                    .get(key)
                    .ok_or_else(|| format!("{path}.{key}: not in the schema"))?;
                conforms(v, sub, &format!("{path}.{key}"))?;
            }
            Ok(())
        }
        other => Err(format!("{path}: {value} is not of type {other:?}")),
    }
}

/// The messages of an MCAP file as `(topic, log_time, body)`, each checked: JSON with a
/// `jsonschema` schema it conforms to, and published at its log time.
fn mcap_messages(path: &Path) -> Vec<(String, u64, Value)> {
    let bytes = std::fs::read(path).unwrap();
    mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            assert_eq!(m.channel.message_encoding, "json");
            assert_eq!(m.log_time, m.publish_time);
            let schema = m.channel.schema.as_ref().expect("schema");
            assert_eq!(schema.encoding, "jsonschema");
            let schema: Value = serde_json::from_slice(&schema.data).expect("schema is JSON");
            let body: Value = serde_json::from_slice(&m.data).unwrap();
            if let Err(e) = conforms(&body, &schema, &m.channel.topic) {
                panic!("message at {} ns: {e}", m.log_time);
            }
            (m.channel.topic.clone(), m.log_time, body)
        })
        .collect()
}

#[test]
fn the_schema_check_rejects_what_does_not_conform() {
    let schema: Value = serde_json::from_str(
        r#"{"type":"object","properties":{"t":{"type":"number"},"name":{"type":"string"}},"required":["t"]}"#,
    )
    .unwrap();
    let ok: Value = serde_json::from_str(r#"{"t":1.5,"name":"brake"}"#).unwrap();
    assert_eq!(conforms(&ok, &schema, "m"), Ok(()));
    for bad in [
        r#"{"name":"brake"}"#,
        r#"{"t":"1.5"}"#,
        r#"{"t":1.5,"name":2}"#,
        r#"{"t":1.5,"x":0}"#,
        r#"{"t":null}"#,
        r#"[1]"#,
    ] {
        let v: Value = serde_json::from_str(bad).unwrap();
        assert!(conforms(&v, &schema, "m").is_err(), "{bad} passed");
    }
}

#[test]
fn json_summary_has_the_spec_names() {
    let v = json(&[]);
    for name in SUMMARY_NAMES {
        assert!(v.get(name).is_some(), "missing `{name}` in {v}");
    }
    for name in ["steps", "rejected", "rhs_evals", "events", "stiff"] {
        assert!(
            v["stats"].get(name).is_some(),
            "missing `stats.{name}` in {v}"
        );
    }
    assert_eq!(v["status"], "ok");
    assert!(v["stats"]["steps"].as_u64().unwrap() > 0);
    // Default scene: hydraulic, the object is hit, the sensor switches, dead time 70 ms.
    let t_detect = f(&v, "t_detect");
    assert!(t_detect > 0.0 && t_detect < 0.3);
    assert!(close(f(&v, "t_brake") - t_detect, 0.070, 1e-9));
    assert!(
        f(&v, "max_gas_pressure") >= 1000.0,
        "gas starts at p10 = 1000 Pa"
    );
    assert!(f(&v, "object_final_velocity") > 0.0);
    assert!(close(
        f(&v, "object_final_momentum"),
        0.246 * f(&v, "object_final_velocity"),
        1e-9
    ));
    assert!(v["object_impacts"].as_u64().unwrap() >= 1);
}

#[test]
fn readable_summary_names_fields_and_units() {
    let o = cushion(&[]);
    assert_eq!(o.status.code(), Some(0));
    let out = stdout(&o);
    for text in [
        "status",
        "ok",
        "t_detect",
        "peak_robot_force",
        " N ",
        "object_final_velocity",
        "m/s",
        "hydraulic",
    ] {
        assert!(out.contains(text), "summary lacks `{text}`:\n{out}");
    }
    // Aligned: every value starts in the same column.
    let value_column = |l: &str| {
        let i = l.find(' ').unwrap();
        i + (l[i..].len() - l[i..].trim_start().len())
    };
    let starts: Vec<usize> = out.lines().map(value_column).collect();
    assert!(
        starts.windows(2).all(|w| w[0] == w[1]),
        "not aligned:\n{out}"
    );
}

#[test]
fn set_changes_the_result() {
    let base = json(&[]);
    let short = json(&["--set", "robot.dead_time=0.01"]);
    assert!(close(
        f(&short, "t_brake") - f(&short, "t_detect"),
        0.010,
        1e-9
    ));
    assert_ne!(
        f(&short, "object_final_velocity"),
        f(&base, "object_final_velocity")
    );

    let bistable = json(&["--set", "module=bistable", "--set", "robot.dead_time=0.01"]);
    assert!(
        bistable["max_gas_pressure"].is_null(),
        "no gas in the bistable module"
    );
    let rigid = json(&["--set", "module=rigid"]);
    assert!(rigid["max_gas_pressure"].is_null());
    // The rigid tool hits harder than the hydraulic module.
    assert!(f(&rigid, "peak_robot_force").abs() > f(&base, "peak_robot_force").abs());

    // Integers are accepted for float keys, solver keys are settable.
    let tight = json(&["--set", "object.mass=1", "--set", "solver.rtol=1e-10"]);
    assert!(close(
        f(&tight, "object_final_momentum"),
        f(&tight, "object_final_velocity"),
        1e-9
    ));
}

#[test]
fn scene_file_and_set_agree_and_set_wins() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(
        &scene,
        "module = \"bistable\"\n\n[robot]\ndead_time = 0.01\n",
    )
    .unwrap();
    let from_file = json(&[scene.to_str().unwrap()]);
    let from_set = json(&["--set", "module=bistable", "--set", "robot.dead_time=0.01"]);
    assert_eq!(from_file, from_set);

    let overridden = json(&[
        scene.to_str().unwrap(),
        "--set",
        "module=hydraulic",
        "--set",
        "robot.dead_time=0.07",
    ]);
    assert_eq!(overridden, json(&[]));
}

#[test]
fn csv_and_mcap_agree_with_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("run.csv");
    let mcap = dir.path().join("run.mcap");
    let v = json(&[
        "--csv",
        csv.to_str().unwrap(),
        "--mcap",
        mcap.to_str().unwrap(),
    ]);

    // Only the two requested files, no temporaries left behind.
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["run.csv", "run.mcap"]);

    // CSV
    let (header, rows) = read_csv(&csv);
    assert_eq!(
        header,
        ["t", "x_r", "v_r", "x_t", "v_t", "x_p", "v_p", "s", "p1", "F_c", "F_r"]
    );
    assert!(rows.len() > 100, "{} rows", rows.len());
    assert!(rows.iter().all(|r| r.len() == 11));
    let (it, ixp, ivp, is, ifr) = (
        col(&header, "t"),
        col(&header, "x_p"),
        col(&header, "v_p"),
        col(&header, "s"),
        col(&header, "F_r"),
    );
    let t: Vec<f64> = rows.iter().map(|r| r[it].unwrap()).collect();
    assert_eq!(t[0], 0.0);
    assert!(t.windows(2).all(|w| w[0] <= w[1]), "time ascends");
    let last = rows.last().unwrap();
    assert!(close(
        last[ivp].unwrap(),
        f(&v, "object_final_velocity"),
        1e-9
    ));
    assert!(close(
        last[ixp].unwrap() - rows[0][ixp].unwrap(),
        f(&v, "object_travel"),
        1e-9
    ));
    let max_s = rows.iter().filter_map(|r| r[is]).fold(f64::MIN, f64::max);
    assert!(max_s <= f(&v, "max_stroke") * (1.0 + 1e-9) + 1e-15);
    assert!(max_s >= 0.5 * f(&v, "max_stroke"));
    let peak = f(&v, "peak_robot_force");
    let max_fr = rows
        .iter()
        .filter_map(|r| r[ifr])
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(max_fr <= peak.abs() * (1.0 + 1e-9));
    assert!(max_fr >= 0.5 * peak.abs());

    // MCAP (each message checked against its schema by `mcap_messages`)
    let mut state = Vec::new();
    let mut events = Vec::new();
    for (topic, log_time, body) in mcap_messages(&mcap) {
        match topic.as_str() {
            "/state" => state.push((log_time, body)),
            "/events" => events.push((log_time, body)),
            other => panic!("unexpected topic {other}"),
        }
    }
    assert_eq!(state.len(), rows.len(), "one /state message per CSV row");
    for (i, (log, body)) in state.iter().enumerate() {
        assert_eq!(*log, (t[i] * 1e9).round() as u64);
        assert!(close(body["t"].as_f64().unwrap(), t[i], 1e-15));
    }
    let (_, last_msg) = state.last().unwrap();
    assert!(close(
        last_msg["v_p"].as_f64().unwrap(),
        last[ivp].unwrap(),
        1e-15
    ));
    assert!(close(
        last_msg["F_r"].as_f64().unwrap(),
        last[ifr].unwrap(),
        1e-15
    ));
    for name in [
        "x_r", "v_r", "x_t", "v_t", "x_p", "v_p", "s", "p1", "F_c", "F_r",
    ] {
        assert!(last_msg.get(name).is_some(), "/state lacks {name}");
    }
    let sensor = events
        .iter()
        .find(|(_, e)| e["name"] == "sensor")
        .expect("a sensor event");
    assert!(close(
        sensor.1["t"].as_f64().unwrap(),
        f(&v, "t_detect"),
        1e-15
    ));
    assert!(sensor.0.abs_diff((f(&v, "t_detect") * 1e9).round() as u64) <= 1);
    assert!(sensor.1["point"]["s"].as_f64().unwrap() > 0.0);
    assert!(events.iter().any(|(_, e)| e["name"] == "brake"));
    assert!(
        events.windows(2).all(|w| w[0].0 <= w[1].0),
        "events in time order"
    );
}

#[test]
fn absent_quantities_are_empty_cells() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("bistable.csv");
    json(&["--set", "module=bistable", "--csv", csv.to_str().unwrap()]);
    let (header, rows) = read_csv(&csv);
    let ip1 = col(&header, "p1");
    assert!(
        rows.iter().all(|r| r[ip1].is_none()),
        "no gas: p1 cells are empty"
    );
    assert!(rows.iter().all(|r| r[col(&header, "F_r")].is_some()));
}

#[test]
fn plot_writes_a_figure() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("fig3.svg");
    let o = cushion(&["--plot", svg.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"));
    assert!(text.trim_end().ends_with("</svg>"));
    for label in [
        "Positions",
        "Velocities",
        "Gas pressure",
        "Forces",
        "time [ms]",
        "detection",
        "force on the robot F_r",
    ] {
        assert!(text.contains(label), "figure lacks `{label}`");
    }
    assert!(
        stdout(&o).contains("fig3.svg"),
        "the summary says what was written"
    );
    if let Ok(dir) = std::env::var("CUSHION_FIGURE_DIR") {
        std::fs::copy(&svg, Path::new(&dir).join("simulate_default.svg")).unwrap();
    }
}

#[test]
fn json_stdout_stays_clean_with_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("f.svg");
    let csv = dir.path().join("t.csv");
    // json() asserts stdout is exactly one JSON value.
    json(&[
        "--plot",
        svg.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(svg.exists() && csv.exists());
}

#[test]
fn a_failed_run_still_prints_its_summary_and_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("partial.csv");
    let o = cushion(&[
        "--set",
        "solver.max_steps=10",
        "--json",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_str(&stdout(&o)).expect("one JSON object");
    assert_eq!(v["status"], "max_steps");
    assert!(
        v["message"].as_str().unwrap().contains("10"),
        "{}",
        v["message"]
    );
    // The trajectory up to where the run stopped is written, and ends where the summary does.
    let (header, rows) = read_csv(&csv);
    assert!(!rows.is_empty());
    let last_t = rows.last().unwrap()[col(&header, "t")].unwrap();
    assert!(last_t < 0.3);
    assert!(
        f(&v, "t_peak_robot_force") <= last_t,
        "the summary covers only the recorded run"
    );

    let human = cushion(&["--set", "solver.max_steps=10"]);
    assert_eq!(human.status.code(), Some(1));
    assert!(stdout(&human).contains("max_steps"));
}

#[test]
fn free_tool_without_object() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("free.csv");
    let mcap = dir.path().join("free.mcap");
    let v = json(&[
        "--set",
        "object.enabled=false",
        "--csv",
        csv.to_str().unwrap(),
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    for name in [
        "object_final_velocity",
        "object_final_momentum",
        "object_travel",
        "t_detect",
    ] {
        assert!(
            v[name].is_null(),
            "`{name}` should be null without an object: {v}"
        );
    }
    assert_eq!(v["object_impacts"], 0);
    let (header, rows) = read_csv(&csv);
    assert!(rows
        .iter()
        .all(|r| r[col(&header, "x_p")].is_none() && r[col(&header, "v_p")].is_none()));
    // in MCAP the absent quantities are left out of the messages, which still conform
    let mut n = 0;
    for (topic, _, body) in mcap_messages(&mcap) {
        if topic == "/state" {
            assert!(
                body.get("x_p").is_none() && body.get("v_p").is_none(),
                "absent fields left out"
            );
            assert!(body.get("x_t").is_some());
            n += 1;
        }
    }
    assert_eq!(n, rows.len());
}

#[test]
fn the_default_method_finishes_the_compressible_liquid() {
    // oil's bulk modulus makes the liquid stiff: dp5 alone ends at its million-step limit;
    // the default, auto, switches to Rodas and ends ok in a few thousand evaluations
    let v = json(&["--set", "hydraulic.bulk_modulus=1.5e9"]);
    assert_eq!(v["status"], "ok");
    assert!(v["stats"]["method_switches"].as_u64().unwrap() >= 1);
    assert!(
        v["stats"]["rhs_evals"].as_u64().unwrap() < 20_000,
        "{}",
        v["stats"]
    );
    let o = cushion(&[
        "--set",
        "hydraulic.bulk_modulus=1.5e9",
        "--set",
        "solver.method=dp5",
        "--set",
        "solver.max_steps=20000",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let dp5: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(dp5["status"], "max_steps");
}
