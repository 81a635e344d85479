//! The journal of a sweep in progress: `DIR/.sweep/` holds `state.json` (what is being run:
//! sweep digest, run count, shard, chunk size) and one `chunk-NNNNNNNN.parquet` per finished
//! chunk (plus `chunk-NNNNNNNN.mcap` with its recorded trajectories). Each is written to a
//! temporary file, fsynced and renamed, and the Parquet file last, so a chunk whose Parquet
//! file exists is complete. A file can still be damaged behind the program's back (a disk that
//! filled up under another writer, a copy cut short): on resume every chunk is read back, and
//! one that cannot be is reported, removed and computed again
//! (`tests/runner.rs::a_damaged_chunk_is_recomputed_on_resume`).
//!
//! At the end the final files are assembled from the chunks in run order.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::atomic::AtomicFile;
use crate::engine::RunRow;
use crate::error::{io_err, SweepError};
use crate::parquet_io::{count_failed_batch, read_parquet, write_parquet_atomic};
use crate::summary_table::{write_csv_rows, TableSchema};

/// Name of the working folder inside the output folder.
pub const STATE_DIR: &str = ".sweep";

/// The chunk files of one sweep in progress.
pub struct Journal {
    pub dir: PathBuf,
}

impl Journal {
    pub fn new(out_dir: &Path) -> Journal {
        Journal {
            dir: out_dir.join(STATE_DIR),
        }
    }

    pub fn exists(&self) -> bool {
        self.dir.exists()
    }

    pub fn chunk_path(&self, c: u64, ext: &str) -> PathBuf {
        self.dir.join(format!("chunk-{c:08}.{ext}"))
    }

    pub fn state_path(&self) -> PathBuf {
        self.dir.join("state.json")
    }

    /// The `state.json` of an earlier invocation, if readable.
    pub fn read_state(&self) -> Option<serde_json::Value> {
        fs::read(self.state_path())
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
    }

    /// Finished chunk files (for messages).
    pub fn count_chunks(&self) -> usize {
        fs::read_dir(&self.dir)
            .map(|d| {
                d.filter_map(|e| e.ok())
                    .filter(|e| {
                        let n = e.file_name().to_string_lossy().into_owned();
                        n.starts_with("chunk-") && n.ends_with(".parquet")
                    })
                    .count()
            })
            .unwrap_or(0)
    }

    /// Whether chunk `c` is on disk and reads back whole: `rows` rows of this sweep's columns,
    /// and its MCAP file, when there is one, readable to the end. A chunk that does not is
    /// removed, and the reason returned as a warning; it is then computed again.
    pub fn check_chunk(&self, c: u64, rows: u64, schema: &TableSchema) -> (bool, Option<String>) {
        let pq = self.chunk_path(c, "parquet");
        if !pq.exists() {
            return (false, None);
        }
        let problem = match read_back(&pq, schema) {
            Err(e) => Some(e),
            Ok(n) if n != rows => Some(format!("{n} rows where {rows} were written")),
            Ok(_) => {
                let mc = self.chunk_path(c, "mcap");
                if mc.exists() {
                    fs::read(&mc)
                        .map_err(|e| e.to_string())
                        .and_then(|b| read_mcap_back(&b))
                        .err()
                        .map(|e| format!("{}: {e}", mc.display()))
                } else {
                    None
                }
            }
        };
        match problem {
            None => (true, None),
            Some(why) => {
                let _ = fs::remove_file(&pq);
                let _ = fs::remove_file(self.chunk_path(c, "mcap"));
                (
                    false,
                    Some(format!(
                        "{} could not be read back ({why}); it is computed again",
                        pq.display()
                    )),
                )
            }
        }
    }

    /// Write one finished chunk: its recorded trajectories (if any) to the chunk's MCAP file,
    /// then its rows to the chunk's Parquet file, whose presence marks the chunk done.
    pub fn write_chunk(
        &self,
        c: u64,
        schema: &TableSchema,
        batch: arrow_array::RecordBatch,
        rows: &[RunRow],
    ) -> Result<(), SweepError> {
        let recorded: Vec<&RunRow> = rows
            .iter()
            .filter(|r| r.result.trajectory.is_some())
            .collect();
        if !recorded.is_empty() {
            let path = self.chunk_path(c, "mcap");
            let mut f = AtomicFile::create(&path).map_err(|e| io_err(path.display(), e))?;
            {
                let mut w = crate::trajectory_mcap::write_options()
                    .create(f.writer())
                    .map_err(|e| io_err(path.display(), e))?;
                for r in &recorded {
                    if let Some(traj) = r.result.trajectory.as_ref() {
                        crate::trajectory_mcap::write_run(
                            &mut w,
                            &format!("/run/{}", r.run),
                            traj,
                            &r.result.events,
                        )
                        .map_err(|e| io_err(path.display(), e))?;
                    }
                }
                w.finish().map_err(|e| io_err(path.display(), e))?;
            }
            f.commit().map_err(|e| io_err(path.display(), e))?;
        }
        write_parquet_atomic(
            &self.chunk_path(c, "parquet"),
            schema,
            std::iter::once(Ok(batch)),
        )
    }

    /// Build `summary.parquet`, `summary.csv` (and `trajectories.mcap`) in `out_dir` from the
    /// chunk files, in run order. Returns the number of rows whose status is not `ok`.
    pub fn assemble(
        &self,
        out_dir: &Path,
        schema: &TableSchema,
        n_chunks: u64,
        recorded: bool,
    ) -> Result<usize, SweepError> {
        let batches = || {
            (0..n_chunks).flat_map(
                move |c| match read_parquet(&self.chunk_path(c, "parquet")) {
                    Ok(it) => Box::new(it) as Box<dyn Iterator<Item = _>>,
                    Err(e) => Box::new(std::iter::once(Err(e))),
                },
            )
        };
        // The CSV (text formatting) on a second thread while this one writes the Parquet file.
        let csv_path = out_dir.join("summary.csv");
        let write_csv = || -> Result<(usize, AtomicFile), SweepError> {
            let mut csv =
                AtomicFile::create(&csv_path).map_err(|e| io_err(csv_path.display(), e))?;
            writeln!(csv.writer(), "{}", schema.csv_header())
                .map_err(|e| io_err(csv_path.display(), e))?;
            let mut failed = 0usize;
            for b in batches() {
                let b = b?;
                failed += count_failed_batch(&b);
                write_csv_rows(csv.writer(), &b).map_err(|e| io_err(csv_path.display(), e))?;
            }
            Ok((failed, csv))
        };
        let (pq, csv) = std::thread::scope(|sc| {
            let h = sc.spawn(write_csv);
            let pq = write_parquet_atomic(&out_dir.join("summary.parquet"), schema, batches());
            (pq, h.join())
        });
        pq?;
        let (failed, csv) =
            csv.map_err(|_| SweepError::Internal("summary.csv: writer thread panicked".into()))??;
        csv.commit().map_err(|e| io_err(csv_path.display(), e))?;

        // Only when a run of this output was recorded (a shard may hold none of the listed runs).
        if recorded && (0..n_chunks).any(|c| self.chunk_path(c, "mcap").exists()) {
            let path = out_dir.join("trajectories.mcap");
            let mut f = AtomicFile::create(&path).map_err(|e| io_err(path.display(), e))?;
            {
                let mut w = crate::trajectory_mcap::write_options()
                    .create(f.writer())
                    .map_err(|e| io_err(path.display(), e))?;
                let mut channels = crate::mcap_copy::ChannelMap::default();
                for c in 0..n_chunks {
                    let p = self.chunk_path(c, "mcap");
                    if !p.exists() {
                        continue;
                    }
                    let bytes = fs::read(&p).map_err(|e| io_err(p.display(), e))?;
                    let stream =
                        mcap::MessageStream::new(&bytes).map_err(|e| io_err(p.display(), e))?;
                    for m in stream {
                        let m = m.map_err(|e| io_err(p.display(), e))?;
                        channels
                            .copy(&mut w, &m)
                            .map_err(|e| io_err(path.display(), e))?;
                    }
                }
                w.finish().map_err(|e| io_err(path.display(), e))?;
            }
            f.commit().map_err(|e| io_err(path.display(), e))?;
        }
        Ok(failed)
    }
}

/// The rows of a chunk's Parquet file, read to the end, with this sweep's columns.
fn read_back(path: &Path, schema: &TableSchema) -> Result<u64, String> {
    let mut n = 0u64;
    for b in read_parquet(path).map_err(|e| e.to_string())? {
        let b = b.map_err(|e| e.to_string())?;
        if b.schema().fields() != schema.arrow.fields() {
            return Err("its columns are not this sweep's".into());
        }
        n += b.num_rows() as u64;
    }
    Ok(n)
}

fn read_mcap_back(bytes: &[u8]) -> Result<(), String> {
    let stream = mcap::MessageStream::new(bytes).map_err(|e| e.to_string())?;
    for m in stream {
        m.map_err(|e| e.to_string())?;
    }
    Ok(())
}
