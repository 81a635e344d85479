//! The runner with a stand-in model: a panicking run is a row, resume is exact, shards split
//! the runs, and the rows come out in run order whatever the thread count.

use std::fs;
use std::path::Path;

use cushion_model::{simulate, RunOptions, RunResult, Scene, Summary};
use cushion_sweep::runner::{run_sweep_with, SweepOptions};

fn write_sweep(dir: &Path, body: &str) -> std::path::PathBuf {
    let p = dir.join("t.toml");
    fs::write(&p, format!("name = \"t\"\n{body}")).unwrap();
    p
}

const BODY: &str = r#"
[set]
t_end = 0.05
[[axis]]
key = "robot.dead_time"
linspace = [0.0, 0.09, 10]
[[axis]]
key = "object.mass"
values = [0.1, 0.5]
[output]
chunk_size = 3
"#;

/// Panics on one run; otherwise the real model.
fn flaky(scene: &Scene, opts: &RunOptions) -> RunResult {
    let dt3 = cushion_sweep::sweep_file::linspace(0.0, 0.09, 10)[3];
    if scene.get("robot.dead_time").unwrap().as_float() == Some(dt3)
        && scene.get("object.mass").unwrap().as_float() == Some(0.5)
    {
        panic!("boom");
    }
    simulate(scene, opts)
}

#[test]
fn a_panicking_run_is_a_row_and_the_rest_run() {
    let dir = tempfile::tempdir().unwrap();
    let f = write_sweep(dir.path(), BODY);
    let out = dir.path().join("o");
    let o = run_sweep_with(
        &SweepOptions {
            file: f,
            out: Some(out.clone()),
            threads: Some(2),
            quiet: true,
            ..Default::default()
        },
        &flaky,
    )
    .unwrap();
    assert_eq!(o.runs_total, 20);
    assert_eq!(o.runs_failed, 1);
    let csv = fs::read_to_string(out.join("summary.csv")).unwrap();
    let row7 = csv.lines().nth(1 + 7).unwrap();
    let dt3 = cushion_sweep::summary_table::csv_float(
        cushion_sweep::sweep_file::linspace(0.0, 0.09, 10)[3],
    );
    let want = format!("7,{dt3},0.5,invalid,internal error: the model panicked: boom");
    assert!(row7.starts_with(&want), "{row7} vs {want}");
    assert_eq!(csv.lines().filter(|l| l.contains(",ok,")).count(), 19);
}

#[test]
fn rows_in_run_order_for_any_thread_count_and_shards_partition() {
    let dir = tempfile::tempdir().unwrap();
    let f = write_sweep(dir.path(), BODY);
    let fake = |scene: &Scene, _: &RunOptions| {
        // Uneven run times, so threads finish out of order.
        let dt = scene.get("robot.dead_time").unwrap().as_float().unwrap();
        std::thread::sleep(std::time::Duration::from_micros(((0.1 - dt) * 2e4) as u64));
        let mut s = Summary::invalid("");
        s.peak_robot_force = dt * 1000.0;
        RunResult {
            summary: s,
            trajectory: None,
            events: Vec::new(),
        }
    };
    let mut outs = Vec::new();
    for t in [1, 2, 3] {
        let out = dir.path().join(format!("t{t}"));
        run_sweep_with(
            &SweepOptions {
                file: f.clone(),
                out: Some(out.clone()),
                threads: Some(t),
                quiet: true,
                ..Default::default()
            },
            &fake,
        )
        .unwrap();
        outs.push(fs::read(out.join("summary.csv")).unwrap());
    }
    assert_eq!(outs[0], outs[1]);
    assert_eq!(outs[0], outs[2]);
    let mut lines = Vec::new();
    for k in 1..=4 {
        let out = dir.path().join(format!("s{k}"));
        let o = run_sweep_with(
            &SweepOptions {
                file: f.clone(),
                out: Some(out.clone()),
                shard: Some((k, 4)),
                quiet: true,
                ..Default::default()
            },
            &fake,
        )
        .unwrap();
        assert_eq!(o.runs_total, 5);
        let text = fs::read_to_string(out.join("summary.csv")).unwrap();
        lines.extend(text.lines().skip(1).map(|l| l.to_string()));
    }
    lines.sort_by_key(|l| l.split(',').next().unwrap().parse::<u32>().unwrap());
    let whole = String::from_utf8(outs[0].clone()).unwrap();
    assert_eq!(lines, whole.lines().skip(1).collect::<Vec<_>>());
}

#[test]
fn final_files_do_not_depend_on_the_chunk_size() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for chunk in [1, 3, 7, 256] {
        let sub = dir.path().join(format!("c{chunk}"));
        fs::create_dir_all(&sub).unwrap();
        let f = write_sweep(
            &sub,
            &BODY.replace("chunk_size = 3", &format!("chunk_size = {chunk}")),
        );
        let out = sub.join("o");
        run_sweep_with(
            &SweepOptions {
                file: f,
                out: Some(out.clone()),
                threads: Some(2),
                quiet: true,
                ..Default::default()
            },
            &simulate,
        )
        .unwrap();
        files.push((
            fs::read(out.join("summary.csv")).unwrap(),
            fs::read(out.join("summary.parquet")).unwrap(),
        ));
    }
    for f in &files[1..] {
        assert!(f.0 == files[0].0 && f.1 == files[0].1);
    }
}

#[test]
fn a_second_sweep_into_a_folder_in_use_is_refused_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let f = write_sweep(dir.path(), BODY);
    let out = dir.path().join("o");
    let opts = SweepOptions {
        file: f,
        out: Some(out.clone()),
        threads: Some(1),
        quiet: true,
        ..Default::default()
    };
    // a sweep writing into `out` now: its lock, as a running sweep holds it
    let running = cushion_sweep::out_lock::OutputLock::take(&out).unwrap();
    let err = run_sweep_with(&opts, &simulate).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains(&out.display().to_string()) && msg.contains("another cushion sweep"),
        "{msg}"
    );
    let mut left: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [cushion_sweep::out_lock::LOCK_FILE],
        "wrote into a folder in use"
    );
    // once it ends, the folder is free again
    drop(running);
    let o = run_sweep_with(&opts, &simulate).unwrap();
    assert_eq!(o.runs_total, 20);
    assert!(out.join("summary.csv").exists());
}
