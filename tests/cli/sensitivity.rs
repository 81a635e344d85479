//! End-to-end `cushion sensitivity`: the command run as a user runs it, with the real model, on
//! a small saltelli sweep of the paper's four axes (N = 16 base points, second order: 160 runs):
//! the files and their columns, the indices' shape (S1, ST per input, S2 per pair, constant
//! outputs reported as such), identical sensitivity.parquet on 1 and 2 threads, failed runs
//! stopping the study with their count or dropping their base points, a stopped study resumed
//! to the same indices, and bad input refused with exit status 2 and nothing written.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use arrow_array::{Array, Float64Array, RecordBatch, StringArray};

use crate::common::{cushion, ok, paper_scene, read_batches, root, s, BIN};

const INPUTS: [&str; 4] = [
    "robot.dead_time",
    "hydraulic.gas_pressure",
    "hydraulic.orifice_radius",
    "object.mass",
];

/// The small study: the paper's four axes, N = 16, 50 resamples; `extra` appended.
fn small(dir: &Path, name: &str, extra: &str) -> PathBuf {
    let text = format!(
        r#"name = "{name}"
scene = {:?}
[set]
"solver.rtol" = 1e-6
[sampling]
mode = "saltelli"
samples = 16
seed = 3
[[axis]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[axis]]
key = "hydraulic.gas_pressure"
range = [300.0, 1e5]
dist = "loguniform"
[[axis]]
key = "hydraulic.orifice_radius"
range = [0.002, 0.012]
[[axis]]
key = "object.mass"
dist = "triangular"
mode = 0.25
range = [0.05, 1.0]
{extra}"#,
        paper_scene()
    );
    let f = dir.join(format!("{name}.toml"));
    fs::write(&f, text).unwrap();
    f
}

/// The one record batch of a small parquet file.
fn read(path: &Path) -> RecordBatch {
    let batches = read_batches(path);
    assert_eq!(batches.len(), 1, "one batch");
    batches[0].clone()
}

fn text_col(b: &RecordBatch, name: &str) -> Vec<Option<String>> {
    let a = b
        .column_by_name(name)
        .unwrap_or_else(|| panic!("column {name}"))
        .as_any()
        .downcast_ref::<StringArray>()
        .unwrap()
        .clone();
    (0..a.len())
        .map(|i| (!a.is_null(i)).then(|| a.value(i).to_string()))
        .collect()
}

fn floats(b: &RecordBatch, name: &str) -> Vec<f64> {
    let a = b
        .column_by_name(name)
        .unwrap()
        .as_any()
        .downcast_ref::<Float64Array>()
        .unwrap()
        .clone();
    (0..a.len())
        .map(|i| if a.is_null(i) { f64::NAN } else { a.value(i) })
        .collect()
}

#[test]
fn files_columns_and_the_same_indices_on_one_and_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let f = small(tmp.path(), "small", "[sensitivity]\nresamples = 50\n");
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let oa = cushion(&["sensitivity", s(&f), "--out", s(&a), "--threads", "1"]);
    ok(&oa);
    ok(&cushion(&[
        "sensitivity",
        s(&f),
        "--out",
        s(&b),
        "--threads",
        "2",
        "--quiet",
    ]));
    for file in [
        "summary.parquet",
        "summary.csv",
        "provenance.json",
        "sweep.toml",
        "sensitivity.parquet",
        "sensitivity.csv",
        "sensitivity.svg",
    ] {
        assert!(a.join(file).is_file(), "{file}");
    }
    let stdout = String::from_utf8_lossy(&oa.stdout);
    assert!(stdout.contains("peak_robot_force: "), "{stdout}");
    assert!(stdout.contains("160 runs (0 not ok)"), "{stdout}");

    // The sample: N (2D + 2) = 160 runs, the inputs in their ranges.
    let summary = read(&a.join("summary.parquet"));
    assert_eq!(summary.num_rows(), 16 * 10);
    let mass = floats(&summary, "object.mass");
    assert!(mass.iter().all(|m| (0.05..=1.0).contains(m)));

    let t = read(&a.join("sensitivity.parquet"));
    let names: Vec<String> = t
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    assert_eq!(
        names,
        ["output", "input", "input_1", "input_2", "index", "value", "conf"]
    );
    let (out, index) = (text_col(&t, "output"), text_col(&t, "index"));
    let (input, i1, i2) = (
        text_col(&t, "input"),
        text_col(&t, "input_1"),
        text_col(&t, "input_2"),
    );
    let (value, conf) = (floats(&t, "value"), floats(&t, "conf"));
    let force: Vec<usize> = (0..t.num_rows())
        .filter(|&r| out[r].as_deref() == Some("peak_robot_force"))
        .collect();
    let kinds: Vec<&str> = force
        .iter()
        .map(|&r| index[r].as_deref().unwrap())
        .collect();
    assert_eq!(
        kinds,
        [["S1"; 4], ["ST"; 4]]
            .concat()
            .into_iter()
            .chain(["S2"; 6])
            .collect::<Vec<_>>()
    );
    for (k, &r) in force[..4].iter().enumerate() {
        assert_eq!(input[r].as_deref(), Some(INPUTS[k]));
        assert!(i1[r].is_none() && i2[r].is_none());
        assert!(value[r].is_finite() && conf[r] >= 0.0);
    }
    assert_eq!(
        (
            i1[force[8]].as_deref(),
            i2[force[8]].as_deref(),
            input[force[8]].as_deref()
        ),
        (Some(INPUTS[0]), Some(INPUTS[1]), None)
    );
    // ST of the most influential input is large; every ST lies in [0, 1] give or take its
    // interval at this small N.
    let st_max = force[4..8].iter().map(|&r| value[r]).fold(0.0, f64::max);
    assert!(st_max > 0.2, "ST max {st_max}");
    // An output missing on some runs (the sensor never switched) is reported, not analysed.
    let missing: Vec<usize> = (0..t.num_rows())
        .filter(|&r| index[r].as_deref() == Some("not_finite"))
        .collect();
    assert!(missing
        .iter()
        .any(|&r| out[r].as_deref() == Some("t_detect")));
    for &r in &missing {
        assert!(value[r] >= 1.0 && value[r] <= 160.0 && conf[r].is_nan() && input[r].is_none());
    }
    let csv = fs::read_to_string(a.join("sensitivity.csv")).unwrap();
    assert_eq!(
        csv.lines().next(),
        Some("output,input,input_1,input_2,index,value,conf")
    );
    assert_eq!(csv.lines().count(), t.num_rows() + 1);
    assert!(fs::read_to_string(a.join("sensitivity.svg"))
        .unwrap()
        .contains("<svg"));

    // Threads change nothing, to the byte.
    assert_eq!(
        fs::read(a.join("sensitivity.parquet")).unwrap(),
        fs::read(b.join("sensitivity.parquet")).unwrap()
    );
    assert_eq!(
        fs::read(a.join("sensitivity.csv")).unwrap(),
        fs::read(b.join("sensitivity.csv")).unwrap()
    );
}

#[test]
fn constant_outputs_are_reported_as_such() {
    // The bistable module never turns stiff here: the stiffness counters are 0 on every run.
    let tmp = tempfile::tempdir().unwrap();
    let text = format!(
        "scene = {:?}\n[sampling]\nmode = \"saltelli\"\nsamples = 8\nsecond_order = false\n[[axis]]\nkey = \"robot.dead_time\"\nrange = [0.04, 0.1]\n[[axis]]\nkey = \"object.mass\"\nrange = [0.05, 1.0]\n[sensitivity]\nresamples = 10\noutputs = [\"stats_stiff\", \"peak_robot_force\"]\n",
        root().join("sweeps/scenes/paper-bistable-dt70.toml")
    );
    let f = tmp.path().join("bistable.toml");
    fs::write(&f, text).unwrap();
    let out = tmp.path().join("out");
    ok(&cushion(&[
        "sensitivity",
        s(&f),
        "--out",
        s(&out),
        "--quiet",
    ]));
    let t = read(&out.join("sensitivity.parquet"));
    assert_eq!(read(&out.join("summary.parquet")).num_rows(), 8 * 4);
    let (o, index, value) = (
        text_col(&t, "output"),
        text_col(&t, "index"),
        floats(&t, "value"),
    );
    assert_eq!(o[0].as_deref(), Some("stats_stiff"));
    assert_eq!((index[0].as_deref(), value[0]), (Some("constant"), 0.0));
    // Without second order: S1 and ST of the two inputs, no S2.
    let force: Vec<&str> = (1..t.num_rows())
        .map(|r| index[r].as_deref().unwrap())
        .collect();
    assert_eq!(force, ["S1", "S1", "ST", "ST"]);
}

#[test]
fn failed_runs_stop_the_study_with_their_count() {
    let tmp = tempfile::tempdir().unwrap();
    // Two solver steps end every run with status max_steps.
    let f = small(
        tmp.path(),
        "failing",
        "[sensitivity]\nresamples = 10\noutputs = [\"peak_robot_force\"]\n",
    );
    let text = fs::read_to_string(&f).unwrap().replace(
        "\"solver.rtol\" = 1e-6\n",
        "\"solver.rtol\" = 1e-6\n\"solver.max_steps\" = 2\n",
    );
    fs::write(&f, &text).unwrap();
    let out = tmp.path().join("failing");
    let o = cushion(&["sensitivity", s(&f), "--out", s(&out), "--quiet"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("160 of 160 runs did not end ok"), "{err}");
    assert!(err.contains("run 0 (robot.dead_time = "), "{err}");
    assert!(err.contains("on_failed = \"drop_base_point\""), "{err}");
    assert!(
        out.join("summary.parquet").is_file(),
        "the sweep's files are kept"
    );
    assert!(!out.join("sensitivity.parquet").exists());
    // Dropping every base point leaves nothing: said so, exit 1.
    fs::write(
        &f,
        text.replace(
            "resamples = 10\n",
            "resamples = 10\non_failed = \"drop_base_point\"\n",
        ),
    )
    .unwrap();
    let o = cushion(&[
        "sensitivity",
        s(&f),
        "--out",
        s(&tmp.path().join("dropped")),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("every base point holds one"), "{err}");
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str, &str)] = &[
        (
            "mode = \"saltelli\"",
            "mode = \"sobol\"",
            "needs mode = \"saltelli\"",
        ),
        (
            "",
            "[sensitivity]\noutputs = [\"peak_force\"]\n",
            "[sensitivity] outputs = \"peak_force\": not a numeric summary field",
        ),
        (
            "",
            "[sensitivity]\nresamples = 1\n",
            "[sensitivity] resamples = 1",
        ),
        (
            "",
            "[sensitivity]\non_failed = \"ignore\"\n",
            "[sensitivity] on_failed = \"ignore\"",
        ),
        (
            "",
            "[sensitivity]\nconf_level = 95\n",
            "[sensitivity] conf_level = 95",
        ),
        (
            "samples = 16",
            "samples = 10",
            "samples = 10: saltelli takes a power of two",
        ),
        (
            "mode = 0.25",
            "mode = 2.0",
            "object.mass: mode = 2: must lie in the range [0.05, 1]",
        ),
        (
            "range = [0.0, 0.1]",
            "values = [0.0, 0.1]",
            "`robot.dead_time`): a saltelli sweep takes only `range` axes",
        ),
        (
            "dist = \"triangular\"\nmode = 0.25\nrange = [0.05, 1.0]",
            "dist = \"normal\"\nmean = 0.3\nsd = 0.1",
            "object.mass must be positive",
        ),
        (
            "dist = \"loguniform\"",
            "dist = \"normal\"\nmean = 1e4\nsd = -1",
            "sd = -1: must be > 0",
        ),
    ];
    for (i, (from, to, want)) in cases.iter().enumerate() {
        let name = format!("bad{i}");
        let f = small(tmp.path(), &name, "");
        let text = fs::read_to_string(&f).unwrap();
        let text = if from.is_empty() {
            format!("{text}{to}")
        } else {
            assert!(text.contains(from), "{from}");
            text.replacen(from, to, 1)
        };
        fs::write(&f, text).unwrap();
        let out = tmp.path().join(format!("out{i}"));
        let o = cushion(&["sensitivity", s(&f), "--out", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{to}: {err}");
        assert!(err.contains(want), "{to}: {err:?} lacks {want:?}");
        assert!(!out.exists(), "{to}: nothing written");
    }
}

#[test]
fn a_stopped_study_resumes_to_the_same_indices() {
    let tmp = tempfile::tempdir().unwrap();
    // 160 runs in chunks of 40: the binary's test hook stops the process after the second.
    let f = small(
        tmp.path(),
        "resumed",
        "[sensitivity]\nresamples = 20\n[output]\nchunk_size = 40\n",
    );
    let whole = tmp.path().join("whole");
    ok(&cushion(&[
        "sensitivity",
        s(&f),
        "--out",
        s(&whole),
        "--quiet",
    ]));

    let part = tmp.path().join("part");
    let o = Command::new(BIN)
        .args(["sensitivity", s(&f), "--out", s(&part), "--quiet"])
        .env("CUSHION_SWEEP_ABORT_AFTER_CHUNKS", "2")
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(99),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!part.join("sensitivity.parquet").exists());
    // Without --resume the unfinished folder is refused, and kept.
    let o = cushion(&["sensitivity", s(&f), "--out", s(&part), "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--resume"));

    ok(&cushion(&[
        "sensitivity",
        s(&f),
        "--out",
        s(&part),
        "--resume",
        "--quiet",
    ]));
    assert_eq!(
        fs::read(whole.join("sensitivity.parquet")).unwrap(),
        fs::read(part.join("sensitivity.parquet")).unwrap()
    );
    assert_eq!(read(&part.join("summary.parquet")).num_rows(), 160);
}

#[test]
fn drop_base_point_analyses_the_other_base_points_and_says_how_many() {
    let tmp = tempfile::tempdir().unwrap();
    // A step limit that only the runs with the most steps reach (long dead times, strong gas).
    let f = small(
        tmp.path(),
        "some",
        "[sensitivity]\nresamples = 10\non_failed = \"drop_base_point\"\n",
    );
    let text = fs::read_to_string(&f).unwrap().replace(
        "\"solver.rtol\" = 1e-6\n",
        "\"solver.rtol\" = 1e-6\n\"solver.max_steps\" = 350\n",
    );
    fs::write(&f, text).unwrap();
    let out = tmp.path().join("some");
    let o = cushion(&["sensitivity", s(&f), "--out", s(&out)]);
    ok(&o);
    let summary = read(&out.join("summary.parquet"));
    let status = text_col(&summary, "status");
    let failed: Vec<bool> = status.iter().map(|s| s.as_deref() != Some("ok")).collect();
    let failed_runs = failed.iter().filter(|&&f| f).count();
    let dropped = failed.chunks(10).filter(|b| b.iter().any(|&f| f)).count();
    assert!(
        failed_runs > 0 && dropped > 0 && dropped < 8,
        "{failed_runs} failed, {dropped} dropped"
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let said = format!(
        "{failed_runs} runs did not end ok: dropped {dropped} of 16 base points (on_failed = \"drop_base_point\")"
    );
    assert!(stdout.contains(&said), "{stdout:?} lacks {said:?}");
    assert!(
        stdout.contains(&format!("160 runs ({failed_runs} not ok)")),
        "{stdout}"
    );
    let t = read(&out.join("sensitivity.parquet"));
    let (output, index, value) = (
        text_col(&t, "output"),
        text_col(&t, "index"),
        floats(&t, "value"),
    );
    let force_s1: Vec<f64> = (0..t.num_rows())
        .filter(|&r| {
            output[r].as_deref() == Some("peak_robot_force") && index[r].as_deref() == Some("S1")
        })
        .map(|r| value[r])
        .collect();
    assert_eq!(force_s1.len(), 4);
    assert!(force_s1.iter().all(|v| v.is_finite()), "{force_s1:?}");
}
