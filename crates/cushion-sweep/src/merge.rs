//! `cushion merge`: join the outputs of `cushion sweep --shard K/N` into one summary equal to
//! the unsharded sweep's (rows sorted by run number, the same columns and the same bytes of CSV),
//! plus the shards' recorded trajectories in one `trajectories.mcap`.
//!
//! Checks before writing anything: every folder is a finished sweep output of the same sweep
//! (same digest of sweep file and base scene), of the same `N`, each shard `1..=N` exactly once,
//! no run twice, and every run of the sweep present.

use std::collections::BTreeMap;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use arrow_array::{Array, Int64Array, RecordBatch};
use arrow_schema::SchemaRef;

use crate::atomic::{write_atomic, AtomicFile};
use crate::error::{io_err, SweepError};
use crate::out_lock::OutputLock;
use crate::parquet_io::{count_failed_batch, read_parquet};
use crate::summary_table::{csv_text, parquet_properties, write_csv_rows};

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

struct Shard {
    dir: PathBuf,
    prov: serde_json::Value,
}

/// Merge shard outputs.
pub fn merge(opts: &MergeOptions) -> Result<MergeOutcome, SweepError> {
    let started = Instant::now();
    if opts.dirs.is_empty() {
        return Err(cfg("merge: give at least one sweep output folder".into()));
    }
    let mut shards = Vec::new();
    for d in &opts.dirs {
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
        shards.push(Shard {
            dir: d.clone(),
            prov,
        });
    }
    let first = &shards[0].prov.clone();
    let n = first["shard"]["n"].as_u64().unwrap_or(1);
    let n_runs = first["n_runs_total"].as_u64().unwrap_or(0);
    let mut seen: BTreeMap<u64, PathBuf> = BTreeMap::new();
    for s in &shards {
        if s.prov["sweep_digest"] != first["sweep_digest"] {
            return Err(cfg(format!(
                "{} and {} hold different sweeps (sweep file or base scene differ)",
                shards[0].dir.display(),
                s.dir.display()
            )));
        }
        if s.prov["shard"]["n"].as_u64() != Some(n) {
            return Err(cfg(format!(
                "{}: shard of {} but {} is a shard of {n}",
                s.dir.display(),
                s.prov["shard"]["n"],
                shards[0].dir.display()
            )));
        }
        let k = s.prov["shard"]["k"].as_u64().unwrap_or(0);
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
    // Shards in k order.
    shards.sort_by_key(|s| s.prov["shard"]["k"].as_u64().unwrap_or(0));

    let name = first["sweep_name"].as_str().unwrap_or("merged").to_string();
    let out_dir = opts
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&name));
    for s in &shards {
        if same_dir(&s.dir, &out_dir) {
            return Err(cfg(format!(
                "--out {} is one of the shards; choose another folder",
                out_dir.display()
            )));
        }
    }
    // One sweep or merge at a time in this folder, until this function returns.
    let lock = OutputLock::take(&out_dir).map_err(|e| e.into_sweep_error(&out_dir))?;
    let mut warnings: Vec<String> = lock.warning(&out_dir).into_iter().collect();

    // Summaries: a k-way merge by run number, streaming.
    let mut readers = Vec::new();
    let mut schema: Option<SchemaRef> = None;
    for s in &shards {
        let p = s.dir.join("summary.parquet");
        let mut it = read_parquet(&p)?.peekable();
        if let Some(Ok(b)) = it.peek() {
            match &schema {
                None => schema = Some(b.schema()),
                Some(sc) if sc.fields() != b.schema().fields() => {
                    return Err(cfg(format!(
                        "{}: columns differ from the other shards",
                        p.display()
                    )))
                }
                _ => {}
            }
        }
        readers.push(it);
    }
    let Some(schema) = schema.or_else(|| read_schema(&shards[0].dir.join("summary.parquet")))
    else {
        return Err(io_err("summary.parquet", "no schema"));
    };

    let csv_path = out_dir.join("summary.csv");
    let mut csv = AtomicFile::create(&csv_path).map_err(|e| io_err(csv_path.display(), e))?;
    let header: Vec<String> = schema.fields().iter().map(|f| csv_text(f.name())).collect();
    writeln!(csv.writer(), "{}", header.join(",")).map_err(|e| io_err(csv_path.display(), e))?;
    let pq_path = out_dir.join("summary.parquet");
    let mut pq = AtomicFile::create(&pq_path).map_err(|e| io_err(pq_path.display(), e))?;
    let mut writer =
        parquet::arrow::ArrowWriter::try_new(pq.take(), schema.clone(), Some(parquet_properties()))
            .map_err(|e| io_err(pq_path.display(), e))?;

    struct Cursor {
        batch: Option<RecordBatch>,
        runs: Option<Int64Array>,
        row: usize,
        slot: usize,
    }
    let mut cursors: Vec<Cursor> = Vec::new();
    let mut slots: Vec<RecordBatch> = Vec::new();
    let load = |it: &mut dyn Iterator<Item = Result<RecordBatch, SweepError>>| -> Result<Option<RecordBatch>, SweepError> {
        loop {
            match it.next() {
                None => return Ok(None),
                Some(b) => {
                    let b = b?;
                    if b.num_rows() > 0 {
                        return Ok(Some(b));
                    }
                }
            }
        }
    };
    let runs_of = |b: &RecordBatch| -> Result<Int64Array, SweepError> {
        b.column_by_name("run")
            .and_then(|c| c.as_any().downcast_ref::<Int64Array>().cloned())
            .ok_or_else(|| io_err("summary.parquet", "no `run` column"))
    };
    for r in readers.iter_mut() {
        let b = load(r)?;
        let runs = b.as_ref().map(&runs_of).transpose()?;
        let slot = slots.len();
        if let Some(b) = &b {
            slots.push(b.clone());
        }
        cursors.push(Cursor {
            batch: b,
            runs,
            row: 0,
            slot,
        });
    }
    let mut picks: Vec<(usize, usize)> = Vec::new();
    let mut last_run: Option<i64> = None;
    let mut count: u64 = 0;
    let mut failed = 0usize;
    const BLOCK: usize = 4096;
    let mut emit = |slots: &[RecordBatch],
                    picks: &[(usize, usize)],
                    failed: &mut usize|
     -> Result<(), SweepError> {
        if picks.is_empty() {
            return Ok(());
        }
        let refs: Vec<&RecordBatch> = slots.iter().collect();
        let out = arrow_select::interleave::interleave_record_batch(&refs, picks)
            .map_err(|e| io_err("merge", e))?;
        *failed += count_failed_batch(&out);
        write_csv_rows(csv.writer(), &out).map_err(|e| io_err(csv_path.display(), e))?;
        writer
            .write(&out)
            .map_err(|e| io_err(pq_path.display(), e))?;
        Ok(())
    };
    loop {
        let mut best: Option<(usize, i64)> = None;
        for (i, c) in cursors.iter().enumerate() {
            if let Some(runs) = &c.runs {
                let r = runs.value(c.row);
                if best.is_none_or(|(_, b)| r < b) {
                    best = Some((i, r));
                }
            }
        }
        let Some((i, run)) = best else { break };
        if last_run == Some(run) {
            return Err(cfg(format!("run {run} appears twice in the shards")));
        }
        last_run = Some(run);
        count += 1;
        let c = &mut cursors[i];
        picks.push((c.slot, c.row));
        c.row += 1;
        if c.row == c.batch.as_ref().map(|b| b.num_rows()).unwrap_or(0) {
            let b = load(&mut readers[i])?;
            c.runs = b.as_ref().map(&runs_of).transpose()?;
            c.row = 0;
            if let Some(b) = &b {
                c.slot = slots.len();
                slots.push(b.clone());
            }
            c.batch = b;
        }
        if picks.len() >= BLOCK {
            emit(&slots, &picks, &mut failed)?;
            picks.clear();
            // Keep only the batches still in use.
            slots.clear();
            for c in cursors.iter_mut() {
                if let Some(b) = &c.batch {
                    c.slot = slots.len();
                    slots.push(b.clone());
                }
            }
        }
    }
    emit(&slots, &picks, &mut failed)?;
    if count != n_runs {
        return Err(cfg(format!(
            "the shards hold {count} runs, the sweep has {n_runs}: a shard is incomplete"
        )));
    }
    let w = writer
        .into_inner()
        .map_err(|e| io_err(pq_path.display(), e))?;
    pq.commit_with(w)
        .map_err(|e| io_err(pq_path.display(), e))?;
    csv.commit().map_err(|e| io_err(csv_path.display(), e))?;

    // Trajectories, merged by run number.
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

    let sweep_copy = shards[0].dir.join("sweep.toml");
    if let Ok(text) = fs::read(&sweep_copy) {
        write_atomic(&out_dir.join("sweep.toml"), &text)
            .map_err(|e| io_err(out_dir.display(), e))?;
    }
    let mut prov = first.clone();
    let wall: f64 = shards
        .iter()
        .filter_map(|s| s.prov["wall_seconds"].as_f64())
        .sum();
    prov["shard"] = serde_json::json!({ "k": 1, "n": 1 });
    prov["runs_in_output"] = serde_json::json!(count);
    prov["runs_failed"] = serde_json::json!(failed);
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
    .map_err(|e| io_err(out_dir.display(), e))?;
    if let Err(e) = crate::report::write_report(&out_dir) {
        warnings.push(format!("report charts not written: {e}"));
    }
    Ok(MergeOutcome {
        out_dir,
        runs: count,
        runs_failed: failed,
        warnings,
    })
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

fn read_schema(path: &Path) -> Option<SchemaRef> {
    let f = fs::File::open(path).ok()?;
    let b = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(f).ok()?;
    Some(b.schema().clone())
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
