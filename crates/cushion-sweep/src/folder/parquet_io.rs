//! Summary tables on disk: Parquet written atomically, read back batch by batch.

use std::fs;
use std::path::Path;

use arrow_array::{Array, RecordBatch, StringArray};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;

use crate::atomic::AtomicFile;
use crate::error::{io_err, SweepError};
use crate::summary_table::{parquet_properties, TableSchema};

/// Write record batches to a Parquet file atomically (temporary file, fsync, rename).
pub fn write_parquet_atomic(
    path: &Path,
    schema: &TableSchema,
    batches: impl Iterator<Item = Result<RecordBatch, SweepError>>,
) -> Result<(), SweepError> {
    let mut f = AtomicFile::create(path).map_err(|e| io_err(path.display(), e))?;
    let w = f.take();
    let mut writer = ArrowWriter::try_new(w, schema.arrow.clone(), Some(parquet_properties()))
        .map_err(|e| io_err(path.display(), e))?;
    for b in batches {
        writer.write(&b?).map_err(|e| io_err(path.display(), e))?;
    }
    let w = writer.into_inner().map_err(|e| io_err(path.display(), e))?;
    f.commit_with(w).map_err(|e| io_err(path.display(), e))
}

/// Read a Parquet file's batches one after the other.
pub fn read_parquet(
    path: &Path,
) -> Result<impl Iterator<Item = Result<RecordBatch, SweepError>>, SweepError> {
    let file = fs::File::open(path).map_err(|e| io_err(path.display(), e))?;
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.with_batch_size(4096).build())
        .map_err(|e| io_err(path.display(), e))?;
    let p = path.display().to_string();
    Ok(reader.map(move |b| b.map_err(|e| io_err(&p, e))))
}

/// Every batch of a Parquet file.
pub fn read_parquet_all(path: &Path) -> Result<Vec<RecordBatch>, SweepError> {
    read_parquet(path)?.collect()
}

/// Rows of a batch whose `status` is not `ok`.
pub fn count_failed_batch(batch: &RecordBatch) -> usize {
    let Some(col) = batch.column_by_name("status") else {
        return 0;
    };
    let Some(a) = col.as_any().downcast_ref::<StringArray>() else {
        return 0;
    };
    a.iter().filter(|s| *s != Some("ok")).count()
}

/// Rows of a Parquet file whose `status` is not `ok`.
pub fn count_failed(path: &Path) -> Result<usize, SweepError> {
    let mut n = 0;
    for b in read_parquet(path)? {
        n += count_failed_batch(&b?);
    }
    Ok(n)
}
