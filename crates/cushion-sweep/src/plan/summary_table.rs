//! The summary table of a sweep: `run`, one column per axis key (named by the key), then
//! `Summary::COLUMNS`. Built generically from `Summary::cells()`; held as Arrow record batches,
//! written as Parquet and as CSV.
//!
//! CSV: a header line, then one line per run; floats in Rust's shortest round-trip form (`0.1`,
//! `1e-7`, `NaN`, `inf`), booleans `true`/`false`, a missing value (e.g. `t_detect` when the
//! sensor never switched) an empty field, text quoted when it holds a comma, quote or newline.

use std::io::Write;
use std::sync::Arc;

use arrow_array::builder::{BooleanBuilder, Float64Builder, Int64Builder, StringBuilder};
use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use cushion_model::{Cell, Summary};
use toml::Value;

use crate::sweep_file::{Axis, AxisKind};

/// The kind of one column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColType {
    Float,
    Int,
    Bool,
    Text,
}

impl ColType {
    fn data_type(self) -> DataType {
        match self {
            ColType::Float => DataType::Float64,
            ColType::Int => DataType::Int64,
            ColType::Bool => DataType::Boolean,
            ColType::Text => DataType::Utf8,
        }
    }
    fn of_cell(c: &Cell) -> ColType {
        match c {
            Cell::Float(_) => ColType::Float,
            Cell::Int(_) => ColType::Int,
            Cell::Bool(_) => ColType::Bool,
            Cell::Text(_) => ColType::Text,
        }
    }
}

/// Columns of a sweep's summary table.
#[derive(Clone, Debug)]
pub struct TableSchema {
    pub columns: Vec<(String, ColType)>,
    pub arrow: SchemaRef,
    /// Number of axis columns (after `run`).
    pub n_axes: usize,
}

impl TableSchema {
    pub fn new(axes: &[Axis]) -> TableSchema {
        let mut columns = vec![("run".to_string(), ColType::Int)];
        for a in axes {
            let t = match a.kind {
                AxisKind::Number => ColType::Float,
                AxisKind::Text => ColType::Text,
                AxisKind::Bool => ColType::Bool,
            };
            columns.push((a.key.clone(), t));
        }
        // The summary's own column kinds, read from a summary's cells (no field is hard-coded).
        let cells = Summary::invalid("").cells();
        assert_eq!(cells.len(), Summary::COLUMNS.len());
        for (name, cell) in Summary::COLUMNS.iter().zip(&cells) {
            columns.push((name.to_string(), ColType::of_cell(cell)));
        }
        let fields: Vec<Field> = columns
            .iter()
            .map(|(n, t)| Field::new(n, t.data_type(), *n != "run"))
            .collect();
        TableSchema {
            columns,
            arrow: Arc::new(Schema::new(fields)),
            n_axes: axes.len(),
        }
    }

    /// The column names, comma-separated (the CSV header, without newline).
    pub fn csv_header(&self) -> String {
        self.columns
            .iter()
            .map(|(n, _)| csv_text(n))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// Index of a column by name.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|(n, _)| n == name)
    }
}

enum ColBuilder {
    Float(Float64Builder),
    Int(Int64Builder),
    Bool(BooleanBuilder),
    Text(StringBuilder),
}

impl ColBuilder {
    fn push(&mut self, c: Cell) {
        match (self, c) {
            (ColBuilder::Float(b), Cell::Float(v)) => b.append_option(v),
            (ColBuilder::Int(b), Cell::Int(v)) => b.append_value(v as i64),
            (ColBuilder::Bool(b), Cell::Bool(v)) => b.append_value(v),
            (ColBuilder::Text(b), Cell::Text(v)) => b.append_value(v),
            (_, c) => panic!("summary cell {c:?} does not match its column kind"),
        }
    }
    fn finish(&mut self) -> ArrayRef {
        match self {
            ColBuilder::Float(b) => Arc::new(b.finish()),
            ColBuilder::Int(b) => Arc::new(b.finish()),
            ColBuilder::Bool(b) => Arc::new(b.finish()),
            ColBuilder::Text(b) => Arc::new(b.finish()),
        }
    }
}

/// Collects rows into a record batch.
pub struct RowsBuilder {
    schema: TableSchema,
    cols: Vec<ColBuilder>,
    rows: usize,
}

impl RowsBuilder {
    pub fn new(schema: &TableSchema) -> RowsBuilder {
        let cols = schema
            .columns
            .iter()
            .map(|(_, t)| match t {
                ColType::Float => ColBuilder::Float(Float64Builder::new()),
                ColType::Int => ColBuilder::Int(Int64Builder::new()),
                ColType::Bool => ColBuilder::Bool(BooleanBuilder::new()),
                ColType::Text => ColBuilder::Text(StringBuilder::new()),
            })
            .collect();
        RowsBuilder {
            schema: schema.clone(),
            cols,
            rows: 0,
        }
    }

    /// One run's row: its number, its axis values, its summary.
    pub fn push(&mut self, run: u64, point: &[Value], summary: &Summary) {
        assert_eq!(point.len(), self.schema.n_axes);
        self.cols[0].push(Cell::Int(run));
        for (i, v) in point.iter().enumerate() {
            let cell = match v {
                Value::Float(f) => Cell::Float(Some(*f)),
                Value::Integer(n) => Cell::Float(Some(*n as f64)),
                Value::Boolean(b) => Cell::Bool(*b),
                Value::String(s) => Cell::Text(s.clone()),
                other => Cell::Text(other.to_string()),
            };
            self.cols[1 + i].push(cell);
        }
        for (j, c) in summary.cells().into_iter().enumerate() {
            self.cols[1 + self.schema.n_axes + j].push(c);
        }
        self.rows += 1;
    }

    pub fn len(&self) -> usize {
        self.rows
    }

    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// The rows so far as a batch; the builder is empty afterwards.
    pub fn finish(&mut self) -> RecordBatch {
        let arrays: Vec<ArrayRef> = self.cols.iter_mut().map(|c| c.finish()).collect();
        self.rows = 0;
        RecordBatch::try_new(self.schema.arrow.clone(), arrays)
            .expect("columns match the schema by construction")
    }
}

/// A CSV field for text: quoted when it holds a comma, quote, CR or LF.
pub fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A float as CSV writes it: shortest round-trip form.
pub fn csv_float(f: f64) -> String {
    if f.is_nan() {
        "NaN".to_string()
    } else if f.is_infinite() {
        if f > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{f:?}")
    }
}

/// Append a batch's rows as CSV lines.
pub fn write_csv_rows(w: &mut impl Write, batch: &RecordBatch) -> std::io::Result<()> {
    let n = batch.num_rows();
    let cols = batch.columns();
    let mut line = String::new();
    for i in 0..n {
        line.clear();
        for (j, col) in cols.iter().enumerate() {
            if j > 0 {
                line.push(',');
            }
            if col.is_null(i) {
                continue;
            }
            match col.data_type() {
                DataType::Float64 => {
                    let a = col.as_any().downcast_ref::<Float64Array>().expect("f64");
                    line.push_str(&csv_float(a.value(i)));
                }
                DataType::Int64 => {
                    let a = col.as_any().downcast_ref::<Int64Array>().expect("i64");
                    line.push_str(&a.value(i).to_string());
                }
                DataType::Boolean => {
                    let a = col.as_any().downcast_ref::<BooleanArray>().expect("bool");
                    line.push_str(if a.value(i) { "true" } else { "false" });
                }
                DataType::Utf8 => {
                    let a = col.as_any().downcast_ref::<StringArray>().expect("utf8");
                    line.push_str(&csv_text(a.value(i)));
                }
                other => panic!("unexpected column type {other}"),
            }
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// Writer properties of every summary Parquet file: fixed row-group size (so the file depends
/// only on its rows, not on how they were chunked), Snappy, no timestamps.
pub fn parquet_properties() -> parquet::file::properties::WriterProperties {
    parquet::file::properties::WriterProperties::builder()
        .set_compression(parquet::basic::Compression::SNAPPY)
        .set_max_row_group_row_count(Some(PARQUET_ROW_GROUP))
        .build()
}

/// Rows per Parquet row group (bounds the writer's memory).
pub const PARQUET_ROW_GROUP: usize = 8192;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields() {
        assert_eq!(csv_text("a,b"), "\"a,b\"");
        assert_eq!(csv_text("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_float(0.1), "0.1");
        assert_eq!(csv_float(1.0), "1.0");
        assert_eq!(csv_float(1e-7), "1e-7");
        assert_eq!("1e-7".parse::<f64>().unwrap(), 1e-7);
    }

    #[test]
    fn schema_follows_summary_columns() {
        let s = TableSchema::new(&[]);
        assert_eq!(s.columns.len(), 1 + Summary::COLUMNS.len());
        assert_eq!(s.columns[1].0, "status");
        let mut b = RowsBuilder::new(&s);
        b.push(3, &[], &Summary::invalid("bad, \"very\""));
        let batch = b.finish();
        let mut out = Vec::new();
        write_csv_rows(&mut out, &batch).unwrap();
        let line = String::from_utf8(out).unwrap();
        assert!(
            line.starts_with("3,invalid,\"bad, \"\"very\"\"\",,,0.0,"),
            "{line}"
        );
    }
}
