//! The merged `summary.parquet` and `summary.csv`: the shards' rows streamed in run order (a
//! k-way merge, written a block of rows at a time), each run once and every run of the sweep
//! present.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::iter::Peekable;
use std::path::{Path, PathBuf};

use arrow_array::{Array, Int64Array, RecordBatch};
use arrow_schema::SchemaRef;
use parquet::arrow::ArrowWriter;

use super::{cfg, Shard};
use crate::atomic::AtomicFile;
use crate::error::{io_err, SweepError};
use crate::parquet_io::{count_failed_batch, read_parquet};
use crate::summary_table::{csv_text, parquet_properties, write_csv_rows};

/// Rows gathered before they are written; the batches they come from stay in memory till then.
const BLOCK: usize = 4096;

/// One shard's summary, batch by batch.
type Batches = Peekable<Box<dyn Iterator<Item = Result<RecordBatch, SweepError>>>>;

/// What the merged summary holds.
pub(super) struct MergedRows {
    pub count: u64,
    /// Rows whose status is not `ok`.
    pub failed: usize,
}

/// Write the merged summary files into `out_dir`; `n_runs` is the sweep's number of runs, which
/// the shards must hold between them.
pub(super) fn merge_summaries(
    shards: &[Shard],
    out_dir: &Path,
    n_runs: u64,
) -> Result<MergedRows, SweepError> {
    let (readers, schema) = open_summaries(shards)?;
    let mut out = SummaryFiles::create(out_dir, &schema)?;
    let mut order = RunOrder::start(readers)?;
    // The rows of the block being gathered: (slot of their batch, row in it).
    let mut picks: Vec<(usize, usize)> = Vec::new();
    let mut last_run: Option<i64> = None;
    let mut rows = MergedRows {
        count: 0,
        failed: 0,
    };
    while let Some((i, run)) = order.lowest() {
        if last_run == Some(run) {
            return Err(cfg(format!("run {run} appears twice in the shards")));
        }
        last_run = Some(run);
        rows.count += 1;
        picks.push(order.take(i)?);
        if picks.len() >= BLOCK {
            rows.failed += out.write(&order.slots, &picks)?;
            picks.clear();
            order.keep_batches_in_use();
        }
    }
    rows.failed += out.write(&order.slots, &picks)?;
    if rows.count != n_runs {
        return Err(cfg(format!(
            "the shards hold {} runs, the sweep has {n_runs}: a shard is incomplete",
            rows.count
        )));
    }
    out.commit()?;
    Ok(rows)
}

/// Each shard's summary, opened, and their columns, which must be the same in every shard.
fn open_summaries(shards: &[Shard]) -> Result<(Vec<Batches>, SchemaRef), SweepError> {
    let mut readers = Vec::new();
    let mut schema: Option<SchemaRef> = None;
    for s in shards {
        let p = s.dir.join("summary.parquet");
        let batches: Box<dyn Iterator<Item = Result<RecordBatch, SweepError>>> =
            Box::new(read_parquet(&p)?);
        let mut it = batches.peekable();
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
    Ok((readers, schema))
}

/// The columns of a Parquet file that has no batch to show them.
fn read_schema(path: &Path) -> Option<SchemaRef> {
    let f = fs::File::open(path).ok()?;
    let b = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(f).ok()?;
    Some(b.schema().clone())
}

/// The two merged files being written; each appears whole on [`SummaryFiles::commit`].
struct SummaryFiles {
    // Fields drop in this order when the merge fails: the Parquet writer before its file.
    parquet: ArrowWriter<BufWriter<File>>,
    pq: AtomicFile,
    pq_path: PathBuf,
    csv: AtomicFile,
    csv_path: PathBuf,
}

impl SummaryFiles {
    /// Start both files: the CSV with its header line, the Parquet with the schema.
    fn create(out_dir: &Path, schema: &SchemaRef) -> Result<SummaryFiles, SweepError> {
        let csv_path = out_dir.join("summary.csv");
        let mut csv = AtomicFile::create(&csv_path).map_err(|e| io_err(csv_path.display(), e))?;
        let header: Vec<String> = schema.fields().iter().map(|f| csv_text(f.name())).collect();
        writeln!(csv.writer(), "{}", header.join(","))
            .map_err(|e| io_err(csv_path.display(), e))?;
        let pq_path = out_dir.join("summary.parquet");
        let mut pq = AtomicFile::create(&pq_path).map_err(|e| io_err(pq_path.display(), e))?;
        let parquet = ArrowWriter::try_new(pq.take(), schema.clone(), Some(parquet_properties()))
            .map_err(|e| io_err(pq_path.display(), e))?;
        Ok(SummaryFiles {
            parquet,
            pq,
            pq_path,
            csv,
            csv_path,
        })
    }

    /// Append the picked rows (slot of their batch, row in it), in order, to both files; how
    /// many of them are not `ok`.
    fn write(
        &mut self,
        slots: &[RecordBatch],
        picks: &[(usize, usize)],
    ) -> Result<usize, SweepError> {
        if picks.is_empty() {
            return Ok(0);
        }
        let refs: Vec<&RecordBatch> = slots.iter().collect();
        let out = arrow_select::interleave::interleave_record_batch(&refs, picks)
            .map_err(|e| io_err("merge", e))?;
        let failed = count_failed_batch(&out);
        write_csv_rows(self.csv.writer(), &out).map_err(|e| io_err(self.csv_path.display(), e))?;
        self.parquet
            .write(&out)
            .map_err(|e| io_err(self.pq_path.display(), e))?;
        Ok(failed)
    }

    /// Finish the Parquet file, then put both files in place.
    fn commit(self) -> Result<(), SweepError> {
        let w = self
            .parquet
            .into_inner()
            .map_err(|e| io_err(self.pq_path.display(), e))?;
        self.pq
            .commit_with(w)
            .map_err(|e| io_err(self.pq_path.display(), e))?;
        self.csv
            .commit()
            .map_err(|e| io_err(self.csv_path.display(), e))
    }
}

/// Where one shard's summary stands: its current batch, that batch's run numbers, the next row.
struct Cursor {
    batch: Option<RecordBatch>,
    runs: Option<Int64Array>,
    row: usize,
    /// The batch's place in [`RunOrder::slots`].
    slot: usize,
}

/// The shards' summaries read side by side, the smallest run number first.
struct RunOrder {
    readers: Vec<Batches>,
    cursors: Vec<Cursor>,
    /// The batches the rows picked since the last write come from.
    slots: Vec<RecordBatch>,
}

impl RunOrder {
    /// Every shard at its first row.
    fn start(mut readers: Vec<Batches>) -> Result<RunOrder, SweepError> {
        let mut cursors = Vec::new();
        let mut slots = Vec::new();
        for r in readers.iter_mut() {
            let b = next_batch_with_rows(r)?;
            let runs = b.as_ref().map(run_numbers).transpose()?;
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
        Ok(RunOrder {
            readers,
            cursors,
            slots,
        })
    }

    /// The shard whose next row has the smallest run number (the first such shard on a tie),
    /// and that run; `None` once every shard is read.
    fn lowest(&self) -> Option<(usize, i64)> {
        let mut best: Option<(usize, i64)> = None;
        for (i, c) in self.cursors.iter().enumerate() {
            if let Some(runs) = &c.runs {
                let r = runs.value(c.row);
                if best.is_none_or(|(_, b)| r < b) {
                    best = Some((i, r));
                }
            }
        }
        best
    }

    /// Shard `i`'s next row as (slot, row), and move past it, on to the shard's next batch
    /// when this one is used up.
    fn take(&mut self, i: usize) -> Result<(usize, usize), SweepError> {
        let c = &mut self.cursors[i];
        let pick = (c.slot, c.row);
        c.row += 1;
        if c.row == c.batch.as_ref().map(|b| b.num_rows()).unwrap_or(0) {
            let b = next_batch_with_rows(&mut self.readers[i])?;
            c.runs = b.as_ref().map(run_numbers).transpose()?;
            c.row = 0;
            if let Some(b) = &b {
                c.slot = self.slots.len();
                self.slots.push(b.clone());
            }
            c.batch = b;
        }
        Ok(pick)
    }

    /// After a block is written: keep only the batches still in use.
    fn keep_batches_in_use(&mut self) {
        self.slots.clear();
        for c in self.cursors.iter_mut() {
            if let Some(b) = &c.batch {
                c.slot = self.slots.len();
                self.slots.push(b.clone());
            }
        }
    }
}

/// The next batch that has rows; `None` at the end of the file.
fn next_batch_with_rows(it: &mut Batches) -> Result<Option<RecordBatch>, SweepError> {
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
}

/// A summary batch's `run` column.
fn run_numbers(b: &RecordBatch) -> Result<Int64Array, SweepError> {
    b.column_by_name("run")
        .and_then(|c| c.as_any().downcast_ref::<Int64Array>().cloned())
        .ok_or_else(|| io_err("summary.parquet", "no `run` column"))
}
