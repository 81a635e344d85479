//! A design question answered through the sweep engine with a stand-in model whose answer is
//! known in closed form: the worst case (an interior peak in the dead time), the boundary of
//! the feasible region, failed runs, the chosen design, classification by the refined map,
//! the files, and a cancelled question that leaves its folder as it was.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use cushion_design::output::{run_design_with, DesignOptions, OUTPUT_FILES};
use cushion_design::{compute_design_with, design_table, DesignFile};
use cushion_model::{RunOptions, RunResult, RunStatus, Scene, Summary};
use cushion_sweep::{Hooks, SweepError};
use toml::Value;

const QUESTION: &str = r#"
name = "stand-in"
[[design]]
key = "hydraulic.orifice_radius"
range = [0.002, 0.012]
[[for_all]]
key = "object.mass"
range = [0.05, 1.0]
[[for_all]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[limit]]
metric = "peak_robot_force"
max = 40.0
abs = true
[search]
resolution = 0.015625
verify = 11
"#;

fn question() -> DesignFile {
    DesignFile::from_str_at(QUESTION, Path::new("/nowhere/stand-in.toml")).unwrap()
}

fn number(scene: &Scene, key: &str) -> f64 {
    match scene.get(key).unwrap() {
        Value::Float(f) => f,
        Value::Integer(i) => i as f64,
        v => panic!("{key} = {v}"),
    }
}

/// The design coordinate `x` in [0, 1] of an orifice radius.
fn x_of(r: f64) -> f64 {
    (r - 0.002) / 0.01
}

/// `F = -(30 m + 5 sin(pi t / 0.1)) (0.5 + x)`: worst `|F| = 35 (0.5 + x)` at `m = 1`,
/// `t = 0.05` (inside the box); feasible (`|F| <= 40`) for `x <= 8/7 - 1/2 = 0.642857`. Runs
/// with `x > 0.9` and `m > 0.9` end at their step limit.
fn stand_in(scene: &Scene, _: &RunOptions) -> RunResult {
    let x = x_of(number(scene, "hydraulic.orifice_radius"));
    let m = number(scene, "object.mass");
    let t = number(scene, "robot.dead_time");
    let mut summary = Summary::invalid("");
    if x > 0.9 && m > 0.9 {
        summary.status = RunStatus::MaxSteps;
        summary.message = "stand-in: step limit".into();
    } else {
        summary.status = RunStatus::Ok;
        summary.message.clear();
        summary.peak_robot_force =
            -(30.0 * m + 5.0 * (std::f64::consts::PI * t / 0.1).sin()) * (0.5 + x);
    }
    RunResult {
        summary,
        trajectory: None,
        events: Vec::new(),
    }
}

const X_EDGE: f64 = 8.0 / 7.0 - 0.5;

#[test]
fn the_answer_of_a_known_question() {
    let r = compute_design_with(question(), Some(2), &Hooks::default(), &stand_in).unwrap();
    // The chosen design: the smallest orifice, |F| = 17.5 N at m = 1 and the peak t = 0.05
    // (between the coarse grid's points 0.025 and 0.075? no: 0.05 is the grid's middle).
    let best = &r.best;
    assert_eq!(best.design, vec![0.002]);
    assert!(
        (best.worst[0].value + 17.5).abs() < 17.5 * 1e-3,
        "{:?}",
        best.worst
    );
    assert_eq!(best.worst[0].witness[0], 1.0);
    assert!((best.worst[0].witness[1] - 0.05).abs() < 1e-3);
    assert!((best.margin - (40.0 - 17.5) / 40.0).abs() < 1e-3);
    assert!(r.verification.all_met);
    assert_eq!(r.verify_runs, 121);

    // Every design point: feasible exactly where x <= 0.642857, failed (margin -inf) where
    // x > 0.9; the worst case within the tolerance of 35 (0.5 + x) elsewhere, never above it.
    for p in r.map.points() {
        let x = x_of(p.design[0]);
        let w = &p.worst[0];
        if x > 0.9 {
            assert!(
                w.failed && !p.feasible && p.margin == f64::NEG_INFINITY,
                "x = {x}"
            );
            continue;
        }
        let truth = 35.0 * (0.5 + x);
        assert!(w.value.abs() <= truth * (1.0 + 1e-12), "x = {x}: {w:?}");
        assert!(w.value.abs() >= truth * (1.0 - 1e-3), "x = {x}: {w:?}");
        assert_eq!(p.feasible, x <= X_EDGE, "x = {x}: {}", w.value);
    }
    // The boundary is refined to the resolution: points within 1/64 on both sides of it.
    let xs: Vec<f64> = r.map.points().iter().map(|p| x_of(p.design[0])).collect();
    assert!(xs.iter().any(|&x| x <= X_EDGE && x > X_EDGE - 1.0 / 64.0));
    assert!(xs.iter().any(|&x| x > X_EDGE && x < X_EDGE + 1.0 / 64.0));
    // The refined map classifies designs away from the boundary right.
    for k in 0..=100 {
        let x = k as f64 / 100.0;
        if (x - X_EDGE).abs() < 1.0 / 64.0 || (x - 0.9).abs() < 1.0 / 64.0 {
            continue;
        }
        let v = [Value::Float(0.002 + 0.01 * x)];
        assert_eq!(r.classify(&v).unwrap(), x <= X_EDGE, "x = {x}");
    }
    assert!(r.classify(&[Value::Float(0.5)]).is_err());

    // The design table: one row per point, the same judgements.
    let t = design_table(&r);
    assert_eq!(t.num_rows(), r.map.points().len());
    let names: Vec<String> = t
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    assert_eq!(
        names,
        [
            "hydraulic.orifice_radius",
            "peak_robot_force.worst",
            "peak_robot_force.at.object.mass",
            "peak_robot_force.at.robot.dead_time",
            "feasible",
            "margin",
            "runs"
        ]
    );
    assert_eq!(r.points_table(), t);
    assert_eq!(r.runs[0].schema(), r.runs_schema());
    assert_eq!(r.answer()["design"]["hydraulic.orifice_radius"], 0.002);
    // Failed runs are in runs.parquet's rows with their status.
    let failed: usize = r
        .runs
        .iter()
        .map(cushion_sweep::parquet_io::count_failed_batch)
        .sum();
    assert!(failed > 0);
    assert_eq!(
        r.runs.iter().map(|b| b.num_rows()).sum::<usize>(),
        r.search_runs + r.verify_runs
    );
}

#[test]
fn a_cancelled_question_leaves_its_folder_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let opts = DesignOptions {
        out: Some(out.clone()),
        threads: Some(2),
        git_commit: None,
    };
    let o = run_design_with(question(), &opts, &Hooks::default(), &stand_in).unwrap();
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
    let before: Vec<Vec<u8>> = OUTPUT_FILES
        .iter()
        .map(|f| std::fs::read(out.join(f)).unwrap())
        .collect();

    // Cancelled after 300 runs (the search spends more): no file changes, no temporary left.
    let cancel = AtomicBool::new(false);
    let progress = |done: u64, _total: u64| {
        if done >= 300 {
            cancel.store(true, Ordering::Relaxed);
        }
    };
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: Some(&cancel),
        chunk_written: None,
    };
    let e = run_design_with(question(), &opts, &hooks, &stand_in).err();
    assert!(matches!(e, Some(SweepError::Cancelled)), "{e:?}");
    for (f, bytes) in OUTPUT_FILES.iter().zip(&before) {
        assert_eq!(&std::fs::read(out.join(f)).unwrap(), bytes, "{f} changed");
    }
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}
