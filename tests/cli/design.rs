//! End-to-end `cushion design`: the command run as a user runs it, with the real model, on a
//! small question (the paper's, at a coarse design resolution of 1/8 and a 5 x 5 verification
//! grid, so it runs in a second): the files and their columns, the witness of every worst case
//! reproduced to the bit by `cushion simulate`, the same answer on 1 and 2 threads, bad input
//! refused with nothing written, Ctrl-C stopping a question with nothing written, and the
//! searched worst cases against a brute-force grid.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use arrow_array::{Array, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray};
use serde_json::Value as Json;

use crate::common::{cushion, ok, paper_scene, read_batches, read_json, root, s, BIN};

const GAS: &str = "hydraulic.gas_pressure";
const ORIFICE: &str = "hydraulic.orifice_radius";
const MASS: &str = "object.mass";
const DEAD_TIME: &str = "robot.dead_time";
const FORCE: &str = "peak_robot_force";
const SPEED: &str = "object_final_velocity";

/// The small question: the paper's design question at a design resolution of 1/8.
fn small_question(dir: &Path) -> PathBuf {
    let text = format!(
        r#"name = "small"
scene = {:?}
[set]
"solver.rtol" = 1e-6
[[design]]
key = "{GAS}"
range = [300.0, 1e5]
scale = "log"
[[design]]
key = "{ORIFICE}"
range = [0.002, 0.012]
[[for_all]]
key = "{MASS}"
range = [0.05, 1.0]
[[for_all]]
key = "{DEAD_TIME}"
range = [0.0, 0.1]
[[limit]]
metric = "{FORCE}"
max = 40.0
abs = true
[[limit]]
metric = "{SPEED}"
max = 1.3
[search]
resolution = 0.125
verify = 5
"#,
        s(&paper_scene())
    );
    let p = dir.join("small.toml");
    fs::write(&p, text).unwrap();
    p
}

/// Answer the small question into `out` on `threads` threads.
fn answer(file: &Path, out: &Path, threads: &str) -> Output {
    let o = cushion(&["design", s(file), "--out", s(out), "--threads", threads]);
    ok(&o);
    o
}

fn columns(b: &[RecordBatch]) -> Vec<String> {
    b[0].schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect()
}

fn rows(b: &[RecordBatch]) -> usize {
    b.iter().map(|b| b.num_rows()).sum()
}

fn floats(b: &[RecordBatch], name: &str) -> Vec<f64> {
    b.iter()
        .flat_map(|b| {
            let c = b.column_by_name(name).unwrap_or_else(|| panic!("{name}"));
            let a = c.as_any().downcast_ref::<Float64Array>().unwrap();
            (0..a.len()).map(|i| a.value(i)).collect::<Vec<_>>()
        })
        .collect()
}

fn texts(b: &[RecordBatch], name: &str) -> Vec<String> {
    b.iter()
        .flat_map(|b| {
            let a = b
                .column_by_name(name)
                .unwrap()
                .as_any()
                .downcast_ref::<StringArray>()
                .unwrap();
            (0..a.len())
                .map(|i| a.value(i).to_string())
                .collect::<Vec<_>>()
        })
        .collect()
}

/// `x` as `--set` takes it: Rust's shortest round-trip form.
fn num(x: f64) -> String {
    format!("{x:?}")
}

#[test]
fn the_files_hold_the_documented_columns_and_agree() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_question(dir.path());
    let out = dir.path().join("out");
    let o = answer(&file, &out, "2");
    let printed = String::from_utf8_lossy(&o.stdout);
    for f in [
        "design.parquet",
        "design.csv",
        "runs.parquet",
        "answer.json",
        "design.toml",
        "provenance.json",
        "design-map.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let leftovers: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // design.parquet: the design keys, per limited metric its worst value and witness,
    // feasible, margin, runs.
    let points = read_batches(&out.join("design.parquet"));
    let mut want = vec![GAS.to_string(), ORIFICE.to_string()];
    for m in [FORCE, SPEED] {
        want.push(format!("{m}.worst"));
        want.push(format!("{m}.at.{MASS}"));
        want.push(format!("{m}.at.{DEAD_TIME}"));
    }
    want.extend(["feasible", "margin", "runs"].map(String::from));
    assert_eq!(columns(&points), want);
    // At 1/8 the 9 x 9 starting corners are the finest lattice: no split is possible.
    assert_eq!(rows(&points), 81);
    let csv = fs::read_to_string(out.join("design.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), want.join(","));
    assert_eq!(csv.lines().count(), 82);

    let a = read_json(&out.join("answer.json"));
    assert_eq!(a["design_points"], 81);
    let runs_at_points: i64 = points
        .iter()
        .flat_map(|b| {
            let c = b.column_by_name("runs").unwrap();
            c.as_any()
                .downcast_ref::<Int64Array>()
                .unwrap()
                .values()
                .to_vec()
        })
        .sum();
    assert_eq!(a["runs"]["search"], runs_at_points);
    // Each design point's search costs at least its 5 x 5 coarse grid.
    assert!(runs_at_points >= 81 * 25, "{runs_at_points}");
    let feasible: usize = points
        .iter()
        .map(|b| {
            let c = b.column_by_name("feasible").unwrap();
            let f = c.as_any().downcast_ref::<BooleanArray>().unwrap();
            f.true_count()
        })
        .sum();
    assert_eq!(a["feasible_points"], feasible);
    assert!(
        feasible > 0 && feasible < 81,
        "{feasible} feasible: the region should be neither empty nor everything"
    );

    // The chosen design is the feasible point of the largest margin.
    let margins = floats(&points, "margin");
    let best_margin = margins.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(a["margin"].as_f64().unwrap(), best_margin);
    assert_eq!(a["feasible"], true);
    let i = margins.iter().position(|&m| m == best_margin).unwrap();
    assert_eq!(a["design"][GAS].as_f64().unwrap(), floats(&points, GAS)[i]);
    assert_eq!(
        a["design"][ORIFICE].as_f64().unwrap(),
        floats(&points, ORIFICE)[i]
    );
    let worst = a["worst"].as_array().unwrap();
    assert_eq!(worst.len(), 2);
    assert_eq!(worst[0]["metric"], FORCE);
    assert_eq!(worst[0]["direction"], "abs_max");
    assert_eq!(
        worst[0]["value"].as_f64().unwrap(),
        floats(&points, &format!("{FORCE}.worst"))[i]
    );
    // The margin is that of the worst cases: |F| under 40 N, speed under 1.3 m/s.
    let f = worst[0]["value"].as_f64().unwrap().abs();
    let v = worst[1]["value"].as_f64().unwrap();
    let m = ((40.0 - f) / 40.0).min((1.3 - v) / 1.3);
    assert!((m - best_margin).abs() < 1e-15, "{m} vs {best_margin}");

    // The verification: 5 x 5 runs at the chosen design, judged.
    let ver = &a["verification"];
    assert_eq!(ver["runs"], 25);
    assert_eq!(a["runs"]["verify"], 25);
    // The searched worst case is at least as bad as the grid's (the grid's points are runs
    // of the same box): the verification's margin is no smaller.
    assert!(ver["margin"].as_f64().unwrap() >= best_margin - 1e-12);
    assert_eq!(ver["all_met"], true);

    // runs.parquet: every run, the sweep summary's columns with stage, design and for_all keys.
    let runs = read_batches(&out.join("runs.parquet"));
    let cols = columns(&runs);
    assert_eq!(
        cols[..6],
        ["run", "stage", GAS, ORIFICE, MASS, DEAD_TIME].map(String::from)
    );
    assert_eq!(cols[6], "status");
    assert!(cols.iter().any(|c| c == "stats_rhs_evals"));
    assert_eq!(rows(&runs) as u64, a["runs"]["total"].as_u64().unwrap());
    let stages = texts(&runs, "stage");
    assert_eq!(stages.iter().filter(|s| *s == "verify").count(), 25);
    assert!(stages[..stages.len() - 25].iter().all(|s| s == "search"));
    // The worst case of every design point is one of its runs, the same number.
    let (g, r, fr) = (
        floats(&runs, GAS),
        floats(&runs, ORIFICE),
        floats(&runs, FORCE),
    );
    let (pg, pr, pw) = (
        floats(&points, GAS),
        floats(&points, ORIFICE),
        floats(&points, &format!("{FORCE}.worst")),
    );
    for k in 0..pg.len() {
        let here: Vec<f64> = (0..g.len())
            .filter(|&j| g[j] == pg[k] && r[j] == pr[k] && stages[j] == "search")
            .map(|j| fr[j])
            .collect();
        let top = here.iter().map(|x| x.abs()).fold(0.0, f64::max);
        assert_eq!(pw[k].abs(), top, "design point {k}");
    }

    let p = read_json(&out.join("provenance.json"));
    assert_eq!(p["design_name"], "small");
    assert_eq!(p["runs_total"], a["runs"]["total"]);
    assert_eq!(p["solver"]["solver.rtol"], 1e-6);
    assert_eq!(
        fs::read(out.join("design.toml")).unwrap(),
        fs::read(&file).unwrap()
    );
    let svg = fs::read_to_string(out.join("design-map.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains(GAS));

    // The printed answer: the design, the worst cases with witnesses, margin, verified, runs.
    for part in [
        "chosen design: hydraulic.gas_pressure = ",
        "peak_robot_force (|peak_robot_force| <= 40): worst ",
        " at object.mass = ",
        "margin ",
        "verified on a grid of 5 per for_all range (25 runs): every run meets every limit",
        "81 design points",
    ] {
        assert!(printed.contains(part), "`{part}` not in:\n{printed}");
    }
}

#[test]
fn every_worst_case_is_reproduced_to_the_bit_by_simulate() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_question(dir.path());
    let out = dir.path().join("out");
    answer(&file, &out, "2");
    let a = read_json(&out.join("answer.json"));
    let design = &a["design"];
    let mut checked = 0;
    for list in [&a["worst"], &a["verification"]["worst"]] {
        for w in list.as_array().unwrap() {
            let metric = w["metric"].as_str().unwrap();
            let mut args = vec![
                "simulate".to_string(),
                s(&paper_scene()).to_string(),
                "--set".into(),
                "solver.rtol=1e-6".into(),
            ];
            for (k, v) in design
                .as_object()
                .unwrap()
                .iter()
                .chain(w["at"].as_object().unwrap())
            {
                args.push("--set".into());
                args.push(format!("{k}={}", num(v.as_f64().unwrap())));
            }
            args.push("--json".into());
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = cushion(&args);
            ok(&o);
            let summary: Json = serde_json::from_slice(&o.stdout).unwrap();
            let (got, want) = (
                summary[metric].as_f64().unwrap(),
                w["value"].as_f64().unwrap(),
            );
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{metric}: simulate gives {got}, the answer {want} ({args:?})"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 4);
}

#[test]
fn the_same_answer_on_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_question(dir.path());
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    answer(&file, &one, "1");
    answer(&file, &two, "2");
    for f in ["design.parquet", "design.csv", "runs.parquet"] {
        assert!(
            fs::read(one.join(f)).unwrap() == fs::read(two.join(f)).unwrap(),
            "{f} differs"
        );
    }
    let strip = |p: &Path| {
        let mut a = read_json(&p.join("answer.json"));
        let m = a.as_object_mut().unwrap();
        m.remove("threads");
        m.remove("wall_seconds");
        a
    };
    assert_eq!(strip(&one), strip(&two));
}

#[test]
fn bad_input_exits_2_with_one_message_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = fs::read_to_string(small_question(dir.path())).unwrap();
    let cases = [
        (
            good.replace(
                "metric = \"object_final_velocity\"",
                "metric = \"final_speed\"",
            ),
            "[[limit]] #2: metric = \"final_speed\"",
        ),
        (
            good.replace(
                "key = \"object.mass\"",
                "key = \"hydraulic.orifice_radius\"",
            ),
            "[[for_all]] #1 (`hydraulic.orifice_radius`): the key is also a [[design]] axis",
        ),
        (
            good.replace("max = 1.3", "max = 1.3\nmin = 2.0"),
            "[[limit]] #2 (`object_final_velocity`): min = 2: at most max (1.3)",
        ),
        (
            good.replace("range = [0.0, 0.1]", "range = [0.1, 0.1]"),
            "robot.dead_time.range = [0.1, 0.1]",
        ),
    ];
    for (i, (text, message)) in cases.iter().enumerate() {
        let f = dir.path().join(format!("bad{i}.toml"));
        fs::write(&f, text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let o = cushion(&["design", s(&f), "--out", s(&out)]);
        assert_eq!(o.status.code(), Some(2), "case {i}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "one message: {err}");
        assert!(err.contains(message), "`{message}` not in: {err}");
        assert!(o.stdout.is_empty());
        assert!(!out.exists(), "case {i}: {} was created", out.display());
    }
    let f = dir.path().join("good.toml");
    fs::write(&f, &good).unwrap();
    let out = dir.path().join("zero");
    let o = cushion(&["design", s(&f), "--out", s(&out), "--threads", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
    let o = cushion(&["design", s(&dir.path().join("missing.toml"))]);
    assert_eq!(o.status.code(), Some(2));
}

/// The worst case of `|force|` and of the speed over a 21 x 21 grid of mass and dead time at
/// one design point, by `cushion sweep`.
fn brute_force(dir: &Path, k: usize, gas: f64, orifice: f64) -> (f64, f64) {
    let text = format!(
        r#"name = "brute{k}"
scene = {:?}
[set]
"solver.rtol" = 1e-6
"{GAS}" = {}
"{ORIFICE}" = {}
[[axis]]
key = "{MASS}"
linspace = [0.05, 1.0, 21]
[[axis]]
key = "{DEAD_TIME}"
linspace = [0.0, 0.1, 21]
"#,
        s(&paper_scene()),
        num(gas),
        num(orifice)
    );
    let f = dir.join(format!("brute{k}.toml"));
    fs::write(&f, text).unwrap();
    let out = dir.join(format!("brute{k}"));
    ok(&cushion(&["sweep", s(&f), "--out", s(&out), "--quiet"]));
    let b = read_batches(&out.join("summary.parquet"));
    assert!(texts(&b, "status").iter().all(|s| s == "ok"));
    let force = floats(&b, FORCE)
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f64::max);
    let speed = floats(&b, SPEED)
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    (force, speed)
}

#[test]
fn searched_worst_cases_are_within_tolerance_of_a_brute_force_grid_or_above() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_question(dir.path());
    let out = dir.path().join("out");
    answer(&file, &out, "2");
    let points = read_batches(&out.join("design.parquet"));
    let (g, r) = (floats(&points, GAS), floats(&points, ORIFICE));
    let (wf, ws) = (
        floats(&points, &format!("{FORCE}.worst")),
        floats(&points, &format!("{SPEED}.worst")),
    );
    let runs: Vec<i64> = points
        .iter()
        .flat_map(|b| {
            b.column_by_name("runs")
                .unwrap()
                .as_any()
                .downcast_ref::<Int64Array>()
                .unwrap()
                .values()
                .to_vec()
        })
        .collect();
    // Six design points over the map (corners, middle, the chosen design's neighbourhood).
    let a = read_json(&out.join("answer.json"));
    let best = (0..g.len())
        .find(|&i| {
            g[i] == a["design"][GAS].as_f64().unwrap()
                && r[i] == a["design"][ORIFICE].as_f64().unwrap()
        })
        .unwrap();
    let tolerance = 1e-3;
    for (k, i) in [0, 8, 40, 72, 80, best].into_iter().enumerate() {
        let (force, speed) = brute_force(dir.path(), k, g[i], r[i]);
        assert!(
            wf[i].abs() >= force * (1.0 - tolerance),
            "design point {i}: searched |F| {} below the grid's {force}",
            wf[i].abs()
        );
        assert!(
            ws[i] >= speed - tolerance * speed.abs(),
            "design point {i}: searched speed {} below the grid's {speed}",
            ws[i]
        );
        // The search spent fewer runs than the grid's 441.
        assert!(runs[i] < 441, "design point {i}: {} runs", runs[i]);
    }
    // In all, under half of a 21 x 21 grid at every design point.
    let total: i64 = runs.iter().sum();
    assert!(
        (total as usize) < runs.len() * 441 / 2,
        "{total} runs for {} design points",
        runs.len()
    );
}

#[test]
fn ctrl_c_stops_a_question_and_writes_nothing() {
    // The README's question at its full resolution, on one thread: seconds of runs, so the
    // interrupt lands while the search is under way.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("stopped");
    let file = root().join("sweeps/design-question.toml");
    let child = Command::new(BIN)
        .args([
            "design",
            s(&file),
            "--out",
            s(&out),
            "--threads",
            "1",
            "--quiet",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("cushion runs");
    std::thread::sleep(std::time::Duration::from_millis(300));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("stopped (interrupted); nothing written"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}
