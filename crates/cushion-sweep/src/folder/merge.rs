//! `cushion merge`: join the outputs of `cushion sweep --shard K/N` into one summary equal to
//! the unsharded sweep's (rows sorted by run number, the same columns and the same bytes of CSV),
//! plus the shards' recorded trajectories in one `trajectories.mcap`.
//!
//! Checks before writing anything: every folder is a finished sweep output of the same sweep
//! (same digest of sweep file and base scene), of the same `N`, each shard `1..=N` exactly once,
//! no run twice, and every run of the sweep present.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::atomic::{write_atomic, AtomicFile};
use crate::error::{io_err, SweepError};
use crate::out_lock::OutputLock;

mod summaries;

use summaries::{merge_summaries, MergedRows};

/// What `cushion merge` was asked.
#[derive(Clone, Debug, Default)]
pub struct MergeOptions {
    pub dirs: Vec<PathBuf>,
    /// Output folder (default: `runs/<sweep name>`).
    pub out: Option<PathBuf>,
}

/// What a merge did.
#[derive(Clone, Debug, Default)]
pub struct MergeOutcome {
    pub out_dir: PathBuf,
    pub runs: u64,
    pub runs_failed: usize,
    /// Things the caller should tell the user; the merge itself succeeded.
    pub warnings: Vec<String>,
}

fn cfg(msg: String) -> SweepError {
    SweepError::Config(msg)
}

/// One shard's output folder and its `provenance.json`.
struct Shard {
    dir: PathBuf,
    prov: serde_json::Value,
}

impl Shard {
    /// Which shard it is (`K` of `--shard K/N`).
    fn k(&self) -> u64 {
        self.prov["shard"]["k"].as_u64().unwrap_or(0)
    }
}

/// Merge shard outputs.
pub fn merge(opts: &MergeOptions) -> Result<MergeOutcome, SweepError> {
    let started = Instant::now();
    let mut shards = read_shard_folders(&opts.dirs)?;
    // The folder named first speaks for the sweep: its name, its number of runs and the
    // provenance the merged one starts from.
    let first = shards[0].prov.clone();
    check_each_shard_once(&shards)?;
    shards.sort_by_key(Shard::k);
    let out_dir = output_folder(opts, &first, &shards)?;
    // One sweep or merge at a time in this folder, until this function returns.
    let lock = OutputLock::take(&out_dir).map_err(|e| e.into_sweep_error(&out_dir))?;
    let mut warnings: Vec<String> = lock.warning(&out_dir).into_iter().collect();

    let n_runs = first["n_runs_total"].as_u64().unwrap_or(0);
    let rows = merge_summaries(&shards, &out_dir, n_runs)?;
    merge_trajectories(&shards, &out_dir)?;
    copy_sweep_file(&shards, &out_dir)?;
    write_provenance(&out_dir, &first, &shards, &rows, started)?;
    if let Err(e) = crate::report::write_report(&out_dir) {
        warnings.push(format!("report charts not written: {e}"));
    }
    Ok(MergeOutcome {
        out_dir,
        runs: rows.count,
        runs_failed: rows.failed,
        warnings,
    })
}

/// Each folder's provenance, in the order given; every folder must be a finished sweep output.
fn read_shard_folders(dirs: &[PathBuf]) -> Result<Vec<Shard>, SweepError> {
    if dirs.is_empty() {
        return Err(cfg("merge: give at least one sweep output folder".into()));
    }
    dirs.iter().map(|d| read_shard_folder(d)).collect()
}

fn read_shard_folder(d: &Path) -> Result<Shard, SweepError> {
    let p = d.join("provenance.json");
    let bytes = fs::read(&p).map_err(|_| {
        cfg(format!(
            "{}: not a finished sweep output (no provenance.json; an unfinished shard needs `cushion sweep --resume`)",
            d.display()
        ))
    })?;
    let prov: serde_json::Value = serde_json::from_slice(&bytes)
        .map_err(|e| cfg(format!("{}: unreadable: {e}", p.display())))?;
    if !d.join("summary.parquet").exists() {
        return Err(cfg(format!("{}: no summary.parquet", d.display())));
    }
    Ok(Shard {
        dir: d.to_path_buf(),
        prov,
    })
}

/// The folders hold one sweep cut into the same `N` shards, and each shard `1..=N` exactly once
/// (the messages name the first folder given as the one the others differ from).
fn check_each_shard_once(shards: &[Shard]) -> Result<(), SweepError> {
    let first = &shards[0];
    let n = first.prov["shard"]["n"].as_u64().unwrap_or(1);
    let mut seen: BTreeMap<u64, PathBuf> = BTreeMap::new();
    for s in shards {
        if s.prov["sweep_digest"] != first.prov["sweep_digest"] {
            return Err(cfg(format!(
                "{} and {} hold different sweeps (sweep file or base scene differ)",
                first.dir.display(),
                s.dir.display()
            )));
        }
        if s.prov["shard"]["n"].as_u64() != Some(n) {
            return Err(cfg(format!(
                "{}: shard of {} but {} is a shard of {n}",
                s.dir.display(),
                s.prov["shard"]["n"],
                first.dir.display()
            )));
        }
        let k = s.k();
        if let Some(other) = seen.insert(k, s.dir.clone()) {
            return Err(cfg(format!(
                "shard {k}/{n} given twice: {} and {}",
                other.display(),
                s.dir.display()
            )));
        }
    }
    let missing: Vec<String> = (1..=n)
        .filter(|k| !seen.contains_key(k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(cfg(format!("missing shard(s): {}", missing.join(", "))));
    }
    Ok(())
}

/// The merged output's folder (default `runs/<sweep name>`), which must not be a shard's.
fn output_folder(
    opts: &MergeOptions,
    first: &serde_json::Value,
    shards: &[Shard],
) -> Result<PathBuf, SweepError> {
    let name = first["sweep_name"].as_str().unwrap_or("merged").to_string();
    let out_dir = opts
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&name));
    for s in shards {
        if same_dir(&s.dir, &out_dir) {
            return Err(cfg(format!(
                "--out {} is one of the shards; choose another folder",
                out_dir.display()
            )));
        }
    }
    Ok(out_dir)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// The shards' `trajectories.mcap`, merged by run number; none when no shard recorded any (and
/// then an old one in the output folder is removed).
fn merge_trajectories(shards: &[Shard], out_dir: &Path) -> Result<(), SweepError> {
    let traj_path = out_dir.join("trajectories.mcap");
    let files: Vec<Vec<u8>> = shards
        .iter()
        .map(|s| s.dir.join("trajectories.mcap"))
        .filter(|p| p.exists())
        .map(|p| fs::read(&p).map_err(|e| io_err(p.display(), e)))
        .collect::<Result<_, _>>()?;
    if files.is_empty() {
        if traj_path.exists() {
            fs::remove_file(&traj_path).map_err(|e| io_err(traj_path.display(), e))?;
        }
    } else {
        merge_mcap(&traj_path, &files)?;
    }
    Ok(())
}

/// The run number of a `/run/<n>/...` topic.
fn topic_run(topic: &str) -> u64 {
    topic
        .strip_prefix("/run/")
        .and_then(|r| r.split('/').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(u64::MAX)
}

fn merge_mcap(path: &Path, files: &[Vec<u8>]) -> Result<(), SweepError> {
    let mut streams = Vec::new();
    for bytes in files {
        let s = mcap::MessageStream::new(bytes).map_err(|e| io_err(path.display(), e))?;
        streams.push(s.peekable());
    }
    let mut f = AtomicFile::create(path).map_err(|e| io_err(path.display(), e))?;
    {
        let mut w = crate::trajectory_mcap::write_options()
            .create(f.writer())
            .map_err(|e| io_err(path.display(), e))?;
        let mut channels = crate::mcap_copy::ChannelMap::default();
        loop {
            let mut best: Option<(usize, u64)> = None;
            for (i, s) in streams.iter_mut().enumerate() {
                match s.peek() {
                    Some(Ok(m)) => {
                        let r = topic_run(&m.channel.topic);
                        if best.is_none_or(|(_, b)| r < b) {
                            best = Some((i, r));
                        }
                    }
                    Some(Err(_)) => {
                        if let Some(Err(e)) = s.next() {
                            return Err(io_err(path.display(), e));
                        }
                    }
                    None => {}
                }
            }
            let Some((i, run)) = best else { break };
            // Copy this run's messages from stream i.
            while let Some(Ok(m)) = streams[i].peek() {
                if topic_run(&m.channel.topic) != run {
                    break;
                }
                let m = streams[i]
                    .next()
                    .expect("peeked")
                    .map_err(|e| io_err(path.display(), e))?;
                channels
                    .copy(&mut w, &m)
                    .map_err(|e| io_err(path.display(), e))?;
            }
        }
        w.finish().map_err(|e| io_err(path.display(), e))?;
    }
    f.commit().map_err(|e| io_err(path.display(), e))
}

/// The sweep file's text, as shard 1 kept it (when it did).
fn copy_sweep_file(shards: &[Shard], out_dir: &Path) -> Result<(), SweepError> {
    let sweep_copy = shards[0].dir.join("sweep.toml");
    if let Ok(text) = fs::read(&sweep_copy) {
        write_atomic(&out_dir.join("sweep.toml"), &text)
            .map_err(|e| io_err(out_dir.display(), e))?;
    }
    Ok(())
}

/// `provenance.json` of the merged output: the first folder's, as one unsharded sweep, with the
/// merged counts, the wall times and invocations of every shard, and which folders it joined.
fn write_provenance(
    out_dir: &Path,
    first: &serde_json::Value,
    shards: &[Shard],
    rows: &MergedRows,
    started: Instant,
) -> Result<(), SweepError> {
    let mut prov = first.clone();
    let wall: f64 = shards
        .iter()
        .filter_map(|s| s.prov["wall_seconds"].as_f64())
        .sum();
    prov["shard"] = serde_json::json!({ "k": 1, "n": 1 });
    prov["runs_in_output"] = serde_json::json!(rows.count);
    prov["runs_failed"] = serde_json::json!(rows.failed);
    prov["wall_seconds"] = serde_json::json!(wall);
    // every invocation of every shard (a shard's own wall time where it predates the fields)
    let all_wall: f64 = shards
        .iter()
        .filter_map(|s| {
            s.prov["wall_seconds_all_invocations"]
                .as_f64()
                .or(s.prov["wall_seconds"].as_f64())
        })
        .sum();
    let invocations: u64 = shards
        .iter()
        .map(|s| s.prov["invocations"].as_u64().unwrap_or(1))
        .sum();
    prov["wall_seconds_all_invocations"] = serde_json::json!(all_wall);
    prov["invocations"] = serde_json::json!(invocations);
    prov["merged_from"] = serde_json::Value::Array(
        shards
            .iter()
            .map(|s| {
                serde_json::json!({
                    "dir": s.dir.display().to_string(),
                    "shard": s.prov["shard"],
                    "threads": s.prov["threads"],
                    "wall_seconds": s.prov["wall_seconds"],
                    "git_commit": s.prov["git_commit"],
                })
            })
            .collect(),
    );
    prov["merge_seconds"] = serde_json::json!(started.elapsed().as_secs_f64());
    write_atomic(
        &out_dir.join("provenance.json"),
        serde_json::to_string_pretty(&prov)
            .unwrap_or_default()
            .as_bytes(),
    )
    .map_err(|e| io_err(out_dir.display(), e))
}
