//! End-to-end `cushion sweep` and `cushion merge`: the command run as a user runs it, with the
//! real model.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use arrow_array::{Array, Float64Array, Int64Array, StringArray};

use crate::common::{cushion, ok, paper_scene, read_batches, read_json, root, s, BIN};

fn cushion_env(args: &[&str], env: (&str, &str)) -> Output {
    Command::new(BIN)
        .args(args)
        .env(env.0, env.1)
        .output()
        .expect("cushion runs")
}

/// A sweep file in `dir`, with the shipped paper scene as its base.
fn sweep_file(dir: &Path, name: &str, body: &str) -> PathBuf {
    let scene = paper_scene();
    let text = format!(
        "name = \"{name}\"\nscene = {:?}\n{body}",
        scene.to_str().unwrap()
    );
    let p = dir.join(format!("{name}.toml"));
    fs::write(&p, text).unwrap();
    p
}

/// 30 runs, lhs over dead time and object mass, both modules, 4 runs per chunk (8 chunks).
const SMALL: &str = r#"
[set]
"t_end" = 0.15
[sampling]
mode = "lhs"
samples = 30
seed = 11
[[axis]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[axis]]
key = "object.mass"
range = [0.05, 1.0]
scale = "log"
[[axis]]
key = "module"
values = ["hydraulic", "bistable"]
[output]
chunk_size = 4
"#;

/// Run the sweep file `f` as `n` shards into `dir/s1`...`dir/sn`; their folders, in order.
fn run_shards(f: &Path, dir: &Path, n: usize) -> Vec<PathBuf> {
    (1..=n)
        .map(|k| {
            let d = dir.join(format!("s{k}"));
            let spec = format!("{k}/{n}");
            ok(&cushion(&[
                "sweep",
                s(f),
                "--out",
                s(&d),
                "--shard",
                &spec,
                "--quiet",
            ]));
            d
        })
        .collect()
}

fn runs_of(p: &Path) -> Vec<i64> {
    read_batches(p)
        .iter()
        .flat_map(|b| {
            let a = b
                .column_by_name("run")
                .unwrap()
                .as_any()
                .downcast_ref::<Int64Array>()
                .unwrap();
            a.values().to_vec()
        })
        .collect()
}

#[test]
fn same_rows_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(dir.path(), "small", SMALL);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    ok(&cushion(&[
        "sweep",
        s(&f),
        "--out",
        s(&a),
        "--threads",
        "1",
        "--quiet",
    ]));
    ok(&cushion(&[
        "sweep",
        s(&f),
        "--out",
        s(&b),
        "--threads",
        "2",
        "--quiet",
    ]));
    let csv = fs::read(a.join("summary.csv")).unwrap();
    assert_eq!(
        csv,
        fs::read(b.join("summary.csv")).unwrap(),
        "CSV differs between 1 and 2 threads"
    );
    assert_eq!(
        fs::read(a.join("summary.parquet")).unwrap(),
        fs::read(b.join("summary.parquet")).unwrap()
    );
    let text = String::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(
        header.starts_with("run,robot.dead_time,object.mass,module,status,message,t_detect,"),
        "{header}"
    );
    assert!(
        header.ends_with(",stats_steps,stats_rejected,stats_rhs_evals,stats_events,stats_stiff,stats_jacobians,stats_lu_decompositions,stats_method_switches")
    );
    assert_eq!(lines.count(), 30);
    assert_eq!(
        runs_of(&a.join("summary.parquet")),
        (0..30).collect::<Vec<_>>()
    );
    // Provenance and the sweep file copy; no working folder left.
    let prov = read_json(&a.join("provenance.json"));
    assert_eq!(prov["threads"], 1);
    assert_eq!(prov["n_runs_total"], 30);
    assert_eq!(prov["solver"]["solver.rtol"], 1e-6);
    assert!(prov["wall_seconds"].as_f64().unwrap() > 0.0);
    assert_eq!(prov["invocations"], 1);
    assert_eq!(prov["wall_seconds_all_invocations"], prov["wall_seconds"]);
    assert_eq!(
        fs::read(a.join("sweep.toml")).unwrap(),
        fs::read(&f).unwrap()
    );
    assert!(!a.join(".sweep").exists());
    assert!(a.join("report-speed-force.svg").exists());
}

#[test]
fn killed_and_resumed_equals_uninterrupted() {
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(dir.path(), "small", SMALL);
    let whole = dir.path().join("whole");
    ok(&cushion(&["sweep", s(&f), "--out", s(&whole), "--quiet"]));

    let part = dir.path().join("part");
    // Stops abruptly (no cleanup) after 3 of 8 chunks.
    let o = cushion_env(
        &[
            "sweep",
            s(&f),
            "--out",
            s(&part),
            "--threads",
            "2",
            "--quiet",
        ],
        ("CUSHION_SWEEP_ABORT_AFTER_CHUNKS", "3"),
    );
    assert_eq!(
        o.status.code(),
        Some(99),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!part.join("summary.csv").exists());
    let chunks = fs::read_dir(part.join(".sweep"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".parquet")
        })
        .count();
    assert_eq!(chunks, 3);

    // Without --resume: refused, nothing lost.
    let o = cushion(&["sweep", s(&f), "--out", s(&part), "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--resume"));

    // Stop once more, then finish.
    let o = cushion_env(
        &["sweep", s(&f), "--out", s(&part), "--resume", "--quiet"],
        ("CUSHION_SWEEP_ABORT_AFTER_CHUNKS", "2"),
    );
    assert_eq!(o.status.code(), Some(99));
    // The two stopped invocations left their running times (up to their last chunk), in the
    // order they started.
    let mut records: Vec<String> = fs::read_dir(part.join(".sweep"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("elapsed-") && n.ends_with(".json"))
        .collect();
    records.sort();
    assert_eq!(records.len(), 2, "{records:?}");
    let earlier: f64 = records
        .iter()
        .map(|n| {
            read_json(&part.join(".sweep").join(n))["seconds"]
                .as_f64()
                .unwrap()
        })
        .sum();
    let o = cushion(&[
        "sweep",
        s(&f),
        "--out",
        s(&part),
        "--resume",
        "--threads",
        "1",
    ]);
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("30 runs (10 computed now"), "{stdout}");
    assert_eq!(
        fs::read(whole.join("summary.csv")).unwrap(),
        fs::read(part.join("summary.csv")).unwrap()
    );
    assert_eq!(
        runs_of(&part.join("summary.parquet")),
        (0..30).collect::<Vec<_>>()
    );
    assert_eq!(
        fs::read(whole.join("summary.parquet")).unwrap(),
        fs::read(part.join("summary.parquet")).unwrap()
    );
    let prov = read_json(&part.join("provenance.json"));
    assert_eq!(prov["runs_computed_now"], 10);
    assert_eq!(prov["resumed"], true);
    // The wall time of this invocation, and of all three (to the ulp that JSON's decimal
    // numbers may cost when read back)
    assert_eq!(prov["invocations"], 3);
    let all = prov["wall_seconds_all_invocations"].as_f64().unwrap();
    let this = prov["wall_seconds"].as_f64().unwrap();
    assert!(
        (all - (earlier + this)).abs() <= 1e-12 * all,
        "{all} vs {earlier} + {this}"
    );

    // --resume on a finished sweep computes nothing.
    let o = cushion(&["sweep", s(&f), "--out", s(&part), "--resume"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("(0 computed now"));

    // --resume with a changed sweep file is refused.
    let o = cushion_env(
        &["sweep", s(&f), "--out", s(&part), "--quiet"],
        ("CUSHION_SWEEP_ABORT_AFTER_CHUNKS", "1"),
    );
    assert_eq!(o.status.code(), Some(99));
    fs::write(
        &f,
        fs::read_to_string(&f)
            .unwrap()
            .replace("seed = 11", "seed = 12"),
    )
    .unwrap();
    let o = cushion(&["sweep", s(&f), "--out", s(&part), "--resume", "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("different sweep"));
}

#[test]
fn really_killed_and_resumed() {
    let dir = tempfile::tempdir().unwrap();
    // One run per chunk, enough runs that the kill lands mid-sweep.
    let body = SMALL
        .replace("samples = 30", "samples = 120")
        .replace("chunk_size = 4", "chunk_size = 1");
    let f = sweep_file(dir.path(), "kill", &body);
    let whole = dir.path().join("whole");
    ok(&cushion(&["sweep", s(&f), "--out", s(&whole), "--quiet"]));
    let part = dir.path().join("part");
    let mut child = Command::new(BIN)
        .args([
            "sweep",
            s(&f),
            "--out",
            s(&part),
            "--threads",
            "2",
            "--quiet",
        ])
        .spawn()
        .unwrap();
    let state = part.join(".sweep");
    let t0 = std::time::Instant::now();
    loop {
        let n = fs::read_dir(&state)
            .map(|d| {
                d.filter(|e| {
                    e.as_ref()
                        .unwrap()
                        .file_name()
                        .to_string_lossy()
                        .ends_with(".parquet")
                })
                .count()
            })
            .unwrap_or(0);
        if n >= 5 || t0.elapsed().as_secs() > 60 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let interrupted = state.exists();
    let o = cushion(&["sweep", s(&f), "--out", s(&part), "--resume", "--quiet"]);
    ok(&o);
    assert_eq!(
        fs::read(whole.join("summary.csv")).unwrap(),
        fs::read(part.join("summary.csv")).unwrap()
    );
    assert_eq!(
        runs_of(&part.join("summary.parquet")),
        (0..120).collect::<Vec<_>>()
    );
    assert!(interrupted, "the sweep finished before it could be killed");
}

#[test]
fn union_of_shards_equals_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let body = SMALL.replace("chunk_size = 4", "chunk_size = 4\nrecord = [0, 4, 6, 28]");
    let f = sweep_file(dir.path(), "small", &body);
    let whole = dir.path().join("whole");
    ok(&cushion(&["sweep", s(&f), "--out", s(&whole), "--quiet"]));
    let shards = run_shards(&f, dir.path(), 3);
    for (k, d) in shards.iter().enumerate() {
        let runs = runs_of(&d.join("summary.parquet"));
        assert_eq!(
            runs,
            (0..30).filter(|r| r % 3 == k as i64).collect::<Vec<_>>()
        );
    }
    // Merging two of three is refused, naming the missing shard.
    let merged = dir.path().join("merged");
    let o = cushion(&["merge", s(&shards[0]), s(&shards[2]), "--out", s(&merged)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing shard(s): 2/3"));
    assert!(!merged.join("summary.csv").exists());

    // Any order.
    ok(&cushion(&[
        "merge",
        s(&shards[2]),
        s(&shards[0]),
        s(&shards[1]),
        "--out",
        s(&merged),
        "--quiet",
    ]));
    assert_eq!(
        fs::read(whole.join("summary.csv")).unwrap(),
        fs::read(merged.join("summary.csv")).unwrap()
    );
    assert_eq!(
        fs::read(whole.join("summary.parquet")).unwrap(),
        fs::read(merged.join("summary.parquet")).unwrap()
    );
    // The merged wall time is every shard's (one invocation each).
    let prov = |d: &Path| read_json(&d.join("provenance.json"));
    let shard_walls: f64 = [2, 0, 1]
        .iter()
        .map(|&k| {
            prov(&shards[k])["wall_seconds_all_invocations"]
                .as_f64()
                .unwrap()
        })
        .sum();
    let m = prov(&merged);
    assert_eq!(m["invocations"], 3);
    assert!(
        (m["wall_seconds_all_invocations"].as_f64().unwrap() - shard_walls).abs() <= 1e-12,
        "{m}"
    );
    // The recorded trajectories, merged in run order, equal the whole sweep's.
    let messages = |p: &Path| -> Vec<(String, u64, Vec<u8>)> {
        let bytes = fs::read(p).unwrap();
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(|m| {
                let m = m.unwrap();
                (m.channel.topic.clone(), m.log_time, m.data.to_vec())
            })
            .collect()
    };
    let whole_msgs = messages(&whole.join("trajectories.mcap"));
    let mut runs: Vec<&str> = whole_msgs
        .iter()
        .map(|m| m.0.split('/').nth(2).unwrap())
        .collect();
    runs.dedup();
    assert_eq!(runs, ["0", "4", "6", "28"]);
    assert_eq!(whole_msgs, messages(&merged.join("trajectories.mcap")));
    assert!(
        !shards[2].join("trajectories.mcap").exists(),
        "shard 3 records no run"
    );
    // A shard given twice is refused.
    let o = cushion(&[
        "merge",
        s(&shards[0]),
        s(&shards[0]),
        s(&shards[1]),
        "--out",
        s(&merged),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("given twice"));
}

#[test]
fn a_failing_run_does_not_stop_the_others() {
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(
        dir.path(),
        "fail",
        r#"
[[axis]]
key = "solver.max_steps"
values = [20, 100000]
[[axis]]
key = "robot.dead_time"
values = [0.01, 0.07]
"#,
    );
    let out = dir.path().join("o");
    let o = cushion(&["sweep", s(&f), "--out", s(&out)]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("4 runs (4 computed now, 2 not ok)"));
    let csv = fs::read_to_string(out.join("summary.csv")).unwrap();
    let status: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap())
        .collect();
    assert_eq!(status, ["max_steps", "max_steps", "ok", "ok"], "{csv}");
    let batches = read_batches(&out.join("summary.parquet"));
    let msg = batches[0]
        .column_by_name("message")
        .unwrap()
        .as_any()
        .downcast_ref::<StringArray>()
        .unwrap()
        .clone();
    assert!(msg.value(0).contains("20"), "{}", msg.value(0));
    assert_eq!(msg.value(2), "");
}

#[test]
fn invalid_sweep_files_fail_before_any_run() {
    let cases: &[(&str, &str)] = &[
        ("colour = 1\n", "unknown key `colour`"),
        ("[sampling]\nmode = \"grid\"\nsead = 3\n", "unknown key `sead` in [sampling]"),
        ("[[axis]]\nkey = \"robot.deadtime\"\nvalues = [0.01]\n", "unknown scene key `robot.deadtime`"),
        ("[[axis]]\nkey = \"robot.dead_time\"\nvalues = []\n", "(`robot.dead_time`): `values` is empty"),
        ("[[axis]]\nkey = \"robot.dead_time\"\nlinspace = [0, 0.1, 0]\n", "n must be an integer >= 1"),
        ("[[axis]]\nkey = \"object.mass\"\nrange = [0.05, 1.0]\n", "a `range` axis needs sampling mode lhs or sobol"),
        (
            "[sampling]\nmode = \"zip\"\n[[axis]]\nkey = \"object.mass\"\nvalues = [0.1, 0.2]\n[[axis]]\nkey = \"robot.dead_time\"\nvalues = [0.01]\n",
            "zip needs axes of one length",
        ),
        ("[[axis]]\nkey = \"object.mass\"\nvalues = [0.1, -1.0]\n", "run 1 (object.mass = -1.0)"),
        ("[[axis]]\nkey = \"module\"\nvalues = [\"hydraulic\", \"pneumatic\"]\n", "run 1 (module = \"pneumatic\")"),
        ("[set]\n\"object.mass\" = \"heavy\"\n", "object.mass"),
        ("[[axis]]\nkey = \"robot.dead_time\"\nvalues = [0.01\n", "line 5, column 15"),
    ];
    for (body, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        let f = sweep_file(dir.path(), "bad", body);
        let out = dir.path().join("o");
        let o = cushion(&["sweep", s(&f), "--out", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{body:?}: {err}");
        assert!(
            err.contains(want),
            "{body:?}: stderr {err:?} lacks {want:?}"
        );
        assert_eq!(err.trim_end().lines().count(), 1, "one message: {err}");
        assert!(!out.exists(), "{body:?}: wrote {out:?}");
        assert!(o.stdout.is_empty());
    }
    // Bad command-line values.
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(dir.path(), "ok", "");
    for args in [["--shard", "4/3"], ["--shard", "0/2"], ["--threads", "0"]] {
        let o = cushion(&[
            "sweep",
            s(&f),
            args[0],
            args[1],
            "--out",
            s(&dir.path().join("o")),
        ]);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!dir.path().join("o").exists());
    }
    let o = cushion(&["sweep", s(&dir.path().join("missing.toml"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing.toml"));
}

#[test]
fn a_folder_another_sweep_is_writing_into_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(dir.path(), "ok", "");
    let out = dir.path().join("o");
    // what a running `cushion sweep --out o` holds
    let running = cushion_sweep::out_lock::OutputLock::take(&out).unwrap();
    let o = cushion(&["sweep", s(&f), "--out", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("another cushion sweep or merge is writing into this folder"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "one message: {err}");
    assert_eq!(fs::read_dir(&out).unwrap().count(), 1, "only the lock file");
    drop(running);
    ok(&cushion(&["sweep", s(&f), "--out", s(&out), "--quiet"]));
    assert!(out.join("summary.parquet").exists());
}

#[test]
fn a_merge_into_a_folder_in_use_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let body = "[set]\nt_end = 0.05\n[[axis]]\nkey = \"robot.dead_time\"\nvalues = [0.01, 0.02]\n";
    let f = sweep_file(dir.path(), "two", body);
    let shards = run_shards(&f, dir.path(), 2);
    let merged = dir.path().join("merged");
    let running = cushion_sweep::out_lock::OutputLock::take(&merged).unwrap();
    let args = [
        "merge",
        s(&shards[0]),
        s(&shards[1]),
        "--out",
        s(&merged),
        "--quiet",
    ];
    let o = cushion(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("is writing into this folder"), "{err}");
    assert_eq!(
        fs::read_dir(&merged).unwrap().count(),
        1,
        "only the lock file"
    );
    drop(running);
    ok(&cushion(&args));
    assert_eq!(runs_of(&merged.join("summary.parquet")), [0, 1]);
}

#[test]
fn a_row_equals_a_single_simulate() {
    let dir = tempfile::tempdir().unwrap();
    let f = sweep_file(
        dir.path(),
        "one",
        r#"
[set]
"object.mass" = 0.5
[sampling]
mode = "zip"
[[axis]]
key = "module"
values = ["hydraulic", "bistable"]
[[axis]]
key = "robot.dead_time"
values = [0.01, 0.07]
[output]
record = [1]
"#,
    );
    let out = dir.path().join("o");
    ok(&cushion(&["sweep", s(&f), "--out", s(&out), "--quiet"]));
    let batches = read_batches(&out.join("summary.parquet"));
    let b = &batches[0];
    assert_eq!(b.num_rows(), 2);
    let scene = paper_scene();
    for (row, module, dt) in [(0usize, "hydraulic", "0.01"), (1, "bistable", "0.07")] {
        let o = cushion(&[
            "simulate",
            s(&scene),
            "--set",
            "object.mass=0.5",
            "--set",
            &format!("module={module}"),
            "--set",
            &format!("robot.dead_time={dt}"),
            "--json",
        ]);
        ok(&o);
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for field in b.schema().fields().iter().skip(3) {
            let name = field.name();
            let col = b.column_by_name(name).unwrap();
            let json = match name.strip_prefix("stats_") {
                Some(stat) => &j["stats"][stat],
                None => &j[name.as_str()],
            };
            if let Some(a) = col.as_any().downcast_ref::<Float64Array>() {
                if a.is_null(row) {
                    assert!(json.is_null(), "{name}: {json}");
                } else {
                    let v = json.as_f64().unwrap_or(f64::NAN);
                    let x = a.value(row);
                    // serde_json's default float parser may be off by an ulp.
                    assert!(
                        (v - x).abs() <= 2.0 * f64::EPSILON * x.abs(),
                        "{name}: {v} vs {x}"
                    );
                }
            } else if let Some(a) = col.as_any().downcast_ref::<Int64Array>() {
                assert_eq!(json.as_i64(), Some(a.value(row)), "{name}");
            } else if let Some(a) = col.as_any().downcast_ref::<StringArray>() {
                assert_eq!(json.as_str(), Some(a.value(row)), "{name}");
            } else if let Some(a) = col.as_any().downcast_ref::<arrow_array::BooleanArray>() {
                assert_eq!(json.as_bool(), Some(a.value(row)), "{name}");
            } else {
                panic!("{name}: unexpected column type");
            }
        }
    }
    // Only run 1 recorded, under /run/1/.
    let bytes = fs::read(out.join("trajectories.mcap")).unwrap();
    let mut topics = std::collections::BTreeSet::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        topics.insert(m.unwrap().channel.topic.clone());
    }
    assert_eq!(
        topics.into_iter().collect::<Vec<_>>(),
        ["/run/1/events", "/run/1/state"]
    );
}

#[test]
fn shipped_paper_sweep_reproduces_the_papers_claims() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("paper");
    ok(&cushion(&[
        "sweep",
        s(&root().join("sweeps/paper.toml")),
        "--out",
        s(&out),
        "--quiet",
    ]));
    let b = &read_batches(&out.join("summary.parquet"))[0];
    let col = |n: &str| {
        b.column_by_name(n)
            .unwrap()
            .as_any()
            .downcast_ref::<Float64Array>()
            .unwrap()
            .clone()
    };
    let module = b
        .column_by_name("module")
        .unwrap()
        .as_any()
        .downcast_ref::<StringArray>()
        .unwrap()
        .clone();
    let (dt, v, f) = (
        col("robot.dead_time"),
        col("object_final_velocity"),
        col("peak_robot_force"),
    );
    let find = |m: &str, d: f64| {
        (0..b.num_rows())
            .find(|i| module.value(*i) == m && dt.value(*i) == d)
            .unwrap()
    };
    for d in [0.01, 0.07] {
        let (h, bi) = (find("hydraulic", d), find("bistable", d));
        assert!(
            f.value(h).abs() < f.value(bi).abs(),
            "robot force lower with hydraulic at {d}"
        );
    }
    assert!(v.value(find("hydraulic", 0.07)).abs() < v.value(find("bistable", 0.07)).abs());
    assert!(v.value(find("bistable", 0.01)).abs() < v.value(find("hydraulic", 0.01)).abs());
    // Six runs' trajectories recorded.
    let bytes = fs::read(out.join("trajectories.mcap")).unwrap();
    let mut topics = std::collections::BTreeSet::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        topics.insert(m.unwrap().channel.topic.clone());
    }
    assert_eq!(topics.len(), 12);
    assert!(topics.contains("/run/5/state"));
}

#[test]
fn shipped_design_space_sweep_parses() {
    // The full sweep is a benchmark; here its first shard of 512 checks the file and the report.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ds");
    let f = root().join("sweeps/design-space.toml");
    let text = fs::read_to_string(&f).unwrap();
    assert!(text.contains("samples = 16384"));
    ok(&cushion(&[
        "sweep",
        s(&f),
        "--out",
        s(&out),
        "--shard",
        "1/512",
        "--quiet",
    ]));
    assert_eq!(
        runs_of(&out.join("summary.parquet")),
        (0..32).map(|i| i * 512).collect::<Vec<_>>()
    );
    assert!(out.join("report-heatmap.svg").exists());
    assert!(out.join("report-speed-force.svg").exists());
}

#[test]
fn shipped_reference_sweep_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ref");
    ok(&cushion(&[
        "sweep",
        s(&root().join("sweeps/reference.toml")),
        "--out",
        s(&out),
        "--quiet",
    ]));
    let csv = fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5);
    assert!(csv
        .lines()
        .nth(4)
        .unwrap()
        .starts_with("3,0.07,100000.0,bistable,ok,"));
    let bytes = fs::read(out.join("trajectories.mcap")).unwrap();
    let mut topics = std::collections::BTreeSet::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        topics.insert(m.unwrap().channel.topic.clone());
    }
    assert_eq!(
        topics.into_iter().collect::<Vec<_>>(),
        [
            "/run/0/events",
            "/run/0/state",
            "/run/3/events",
            "/run/3/state"
        ]
    );
}
