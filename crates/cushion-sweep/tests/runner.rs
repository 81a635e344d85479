//! The runner with a stand-in model: a panicking run is a row, resume is exact, shards split
//! the runs, and the rows come out in run order whatever the thread count.

use std::fs;
use std::path::Path;

use cushion_model::{simulate, RunOptions, RunResult, Scene, Summary};
use cushion_sweep::engine::{compute_with, Hooks, Model, Plan};
use cushion_sweep::runner::{run_sweep_with, SweepOptions, SweepOutcome};
use cushion_sweep::{Runs, SweepError, SweepFile};

fn write_sweep(dir: &Path, body: &str) -> std::path::PathBuf {
    let p = dir.join("t.toml");
    fs::write(&p, format!("name = \"t\"\n{body}")).unwrap();
    p
}

/// Run the sweep file `f` into its folder, with hooks.
fn run_hooked(
    f: &Path,
    opts: &SweepOptions,
    hooks: &Hooks,
    sim: &Model,
) -> Result<SweepOutcome, SweepError> {
    run_sweep_with(SweepFile::from_file(f).unwrap(), opts, hooks, sim)
}

fn run(f: &Path, opts: &SweepOptions, sim: &Model) -> Result<SweepOutcome, SweepError> {
    run_hooked(f, opts, &Hooks::default(), sim)
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
    let o = run(
        &f,
        &SweepOptions {
            out: Some(out.clone()),
            threads: Some(2),
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
        run(
            &f,
            &SweepOptions {
                out: Some(out.clone()),
                threads: Some(t),
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
        let o = run(
            &f,
            &SweepOptions {
                out: Some(out.clone()),
                shard: Some((k, 4)),
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
        run(
            &f,
            &SweepOptions {
                out: Some(out.clone()),
                threads: Some(2),
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
        out: Some(out.clone()),
        threads: Some(1),
        ..Default::default()
    };
    // a sweep writing into `out` now: its lock, as a running sweep holds it
    let running = cushion_sweep::out_lock::OutputLock::take(&out).unwrap();
    let err = run(&f, &opts, &simulate).unwrap_err();
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
    let o = run(&f, &opts, &simulate).unwrap();
    assert_eq!(o.runs_total, 20);
    assert!(out.join("summary.csv").exists());
}

/// Cancel a sweep into `out` once `after` chunk files are on disk.
fn cancelled_after(f: &Path, out: &Path, after: usize) {
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let chunk_written = |n: usize| {
        if n == after {
            cancel.store(true, std::sync::atomic::Ordering::SeqCst);
        }
    };
    let hooks = Hooks {
        cancel: Some(&cancel),
        chunk_written: Some(&chunk_written),
        ..Default::default()
    };
    let opts = SweepOptions {
        out: Some(out.to_path_buf()),
        threads: Some(1),
        ..Default::default()
    };
    let err = run_hooked(f, &opts, &hooks, &simulate).unwrap_err();
    assert!(matches!(err, SweepError::Cancelled), "{err}");
    assert!(!out.join("summary.parquet").exists());
}

fn resume(f: &Path, out: &Path) -> SweepOutcome {
    let opts = SweepOptions {
        out: Some(out.to_path_buf()),
        threads: Some(2),
        resume: true,
        ..Default::default()
    };
    run(f, &opts, &simulate).unwrap()
}

fn whole(f: &Path, out: &Path) -> (Vec<u8>, Vec<u8>) {
    let opts = SweepOptions {
        out: Some(out.to_path_buf()),
        ..Default::default()
    };
    run(f, &opts, &simulate).unwrap();
    (
        fs::read(out.join("summary.csv")).unwrap(),
        fs::read(out.join("summary.parquet")).unwrap(),
    )
}

#[test]
fn a_cancelled_sweep_keeps_its_chunks_and_resume_finishes_it_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let f = write_sweep(dir.path(), BODY);
    let (csv, pq) = whole(&f, &dir.path().join("whole"));
    let out = dir.path().join("o");
    cancelled_after(&f, &out, 2);
    // the runs of the chunk in flight may be lost, no more: chunks 0 and 1 are kept
    let chunks: Vec<_> = fs::read_dir(out.join(".sweep"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".parquet"))
        .collect();
    assert!(chunks.len() >= 2, "{chunks:?}");
    let o = resume(&f, &out);
    assert_eq!(o.runs_total, 20);
    assert_eq!(o.runs_done_now, 20 - 3 * chunks.len());
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
    assert_eq!(fs::read(out.join("summary.csv")).unwrap(), csv);
    assert_eq!(fs::read(out.join("summary.parquet")).unwrap(), pq);
}

#[test]
fn a_damaged_chunk_is_recomputed_on_resume() {
    let dir = tempfile::tempdir().unwrap();
    // a recorded sweep, so that chunks carry MCAP files too
    let body = BODY.replace("chunk_size = 3", "chunk_size = 3\nrecord = [1, 4]");
    let f = write_sweep(dir.path(), &body);
    let (csv, pq) = whole(&f, &dir.path().join("whole"));
    let mcap = fs::read(dir.path().join("whole").join("trajectories.mcap")).unwrap();
    for (damaged, cut) in [
        ("chunk-00000001.parquet", 1000),
        ("chunk-00000001.parquet", 0),
        ("chunk-00000000.mcap", 1000),
    ] {
        let out = dir.path().join(format!("o-{damaged}-{cut}"));
        cancelled_after(&f, &out, 3);
        // as a disk-full stop leaves a file: cut short
        let p = out.join(".sweep").join(damaged);
        let bytes = fs::read(&p).unwrap();
        assert!(bytes.len() > cut, "{damaged}: {} bytes", bytes.len());
        fs::write(&p, &bytes[..cut]).unwrap();
        let o = resume(&f, &out);
        assert_eq!(o.warnings.len(), 1, "{:?}", o.warnings);
        let chunk = damaged.replace(".mcap", ".parquet");
        assert!(
            o.warnings[0].contains(&chunk) && o.warnings[0].contains("computed again"),
            "{:?}",
            o.warnings
        );
        assert_eq!(fs::read(out.join("summary.csv")).unwrap(), csv, "{damaged}");
        assert_eq!(
            fs::read(out.join("summary.parquet")).unwrap(),
            pq,
            "{damaged}"
        );
        assert_eq!(
            fs::read(out.join("trajectories.mcap")).unwrap(),
            mcap,
            "{damaged}"
        );
    }
}

#[test]
fn the_engine_in_memory_gives_the_rows_of_the_summary_file() {
    let dir = tempfile::tempdir().unwrap();
    let f = write_sweep(dir.path(), BODY);
    let out = dir.path().join("o");
    whole(&f, &out);
    let on_disk =
        cushion_sweep::parquet_io::read_parquet_all(&out.join("summary.parquet")).unwrap();
    let on_disk = arrow_select::concat::concat_batches(&on_disk[0].schema(), &on_disk).unwrap();

    let plan = Plan::new(SweepFile::from_file(&f).unwrap()).unwrap();
    let progress_calls = std::sync::atomic::AtomicU64::new(0);
    let progress = |done: u64, total: u64| {
        assert!(done <= total && total == 20);
        progress_calls.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    };
    let hooks = Hooks {
        progress: Some(&progress),
        ..Default::default()
    };
    let batches = compute_with(&plan, Runs::all(20), Some(2), &hooks, &simulate).unwrap();
    assert_eq!(progress_calls.into_inner(), 20);
    let in_memory = arrow_select::concat::concat_batches(&batches[0].schema(), &batches).unwrap();
    assert_eq!(in_memory, on_disk);

    // a range of runs is those rows of the whole
    let part = compute_with(
        &plan,
        Runs::range(20, 5, 12).unwrap(),
        Some(1),
        &Hooks::default(),
        &simulate,
    )
    .unwrap();
    let part = arrow_select::concat::concat_batches(&part[0].schema(), &part).unwrap();
    assert_eq!(part, on_disk.slice(5, 7));

    // cancelled before it starts: nothing runs
    let cancel = std::sync::atomic::AtomicBool::new(true);
    let hooks = Hooks {
        cancel: Some(&cancel),
        ..Default::default()
    };
    let err = compute_with(&plan, Runs::all(20), Some(1), &hooks, &simulate).unwrap_err();
    assert!(matches!(err, SweepError::Cancelled));
}
