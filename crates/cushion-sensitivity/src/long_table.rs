//! The long table of a study (one row per index; the columns are described in
//! [`crate::study`]) and the files it is written to: Parquet, CSV and the chart, each written
//! atomically.

use std::io::Write;
use std::path::Path;
use std::sync::Arc;

use arrow_array::builder::{Float64Builder, StringBuilder};
use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema};

use crate::error::SensitivityError;
use crate::sobol::Sensitivity;
use crate::study::{Finding, Study};

/// The columns of the long table.
pub fn long_schema() -> Arc<Schema> {
    Arc::new(Schema::new(vec![
        Field::new("output", DataType::Utf8, false),
        Field::new("input", DataType::Utf8, true),
        Field::new("input_1", DataType::Utf8, true),
        Field::new("input_2", DataType::Utf8, true),
        Field::new("index", DataType::Utf8, false),
        Field::new("value", DataType::Float64, false),
        Field::new("conf", DataType::Float64, true),
    ]))
}

/// The study as a long table: per output, `S1` and `ST` of each input, then `S2` of each pair
/// (with second order); or one `constant` or `not_finite` row.
pub fn long_table(study: &Study) -> RecordBatch {
    let mut output = StringBuilder::new();
    let mut input = StringBuilder::new();
    let mut input_1 = StringBuilder::new();
    let mut input_2 = StringBuilder::new();
    let mut index = StringBuilder::new();
    let mut value = Float64Builder::new();
    let mut conf = Float64Builder::new();
    let mut row = |o: &str,
                   single: Option<&str>,
                   pair: Option<(&str, &str)>,
                   idx: &str,
                   v: f64,
                   c: Option<f64>| {
        output.append_value(o);
        input.append_option(single);
        input_1.append_option(pair.map(|p| p.0));
        input_2.append_option(pair.map(|p| p.1));
        index.append_value(idx);
        value.append_value(v);
        conf.append_option(c);
    };
    for (name, f) in study.outputs.iter().zip(&study.findings) {
        match f {
            Finding::NotFinite { runs } => row(name, None, None, "not_finite", *runs as f64, None),
            Finding::Sensitivity(Sensitivity::Constant { value }) => {
                row(name, None, None, "constant", *value, None)
            }
            Finding::Sensitivity(Sensitivity::Indices(s)) => {
                for (j, e) in s.s1.iter().enumerate() {
                    row(
                        name,
                        Some(&study.inputs[j]),
                        None,
                        "S1",
                        e.value,
                        Some(e.conf),
                    );
                }
                for (j, e) in s.st.iter().enumerate() {
                    row(
                        name,
                        Some(&study.inputs[j]),
                        None,
                        "ST",
                        e.value,
                        Some(e.conf),
                    );
                }
                for p in &s.s2 {
                    let pair = (study.inputs[p.j].as_str(), study.inputs[p.k].as_str());
                    row(name, None, Some(pair), "S2", p.value, Some(p.conf));
                }
            }
        }
    }
    let columns: Vec<ArrayRef> = vec![
        Arc::new(output.finish()),
        Arc::new(input.finish()),
        Arc::new(input_1.finish()),
        Arc::new(input_2.finish()),
        Arc::new(index.finish()),
        Arc::new(value.finish()),
        Arc::new(conf.finish()),
    ];
    RecordBatch::try_new(long_schema(), columns).expect("the long table's columns fit its schema")
}

fn io(path: &Path, e: impl std::fmt::Display) -> SensitivityError {
    SensitivityError::Io(format!("{}: {e}", path.display()))
}

/// Write `bytes` to `path` through a temporary file in the same folder and a rename, so a
/// reader never sees half a file.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SensitivityError> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(path, e)
    })
}

/// The long table as Parquet.
pub fn parquet_bytes(table: &RecordBatch) -> Result<Vec<u8>, String> {
    let mut buf = Vec::new();
    let mut w = parquet::arrow::ArrowWriter::try_new(&mut buf, table.schema(), None)
        .map_err(|e| e.to_string())?;
    w.write(table).map_err(|e| e.to_string())?;
    w.close().map_err(|e| e.to_string())?;
    Ok(buf)
}

/// The long table as CSV: a header, one line per row; floats in Rust's shortest round-trip
/// form, an empty field for a missing value.
pub fn csv_text(table: &RecordBatch) -> String {
    let mut s = String::new();
    let schema = table.schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    s.push_str(&names.join(","));
    s.push('\n');
    for r in 0..table.num_rows() {
        let cells: Vec<String> = table
            .columns()
            .iter()
            .map(|c| {
                if c.is_null(r) {
                    String::new()
                } else if let Some(a) = c.as_any().downcast_ref::<StringArray>() {
                    let v = a.value(r);
                    if v.contains([',', '"', '\n']) {
                        format!("\"{}\"", v.replace('"', "\"\""))
                    } else {
                        v.to_string()
                    }
                } else if let Some(a) = c.as_any().downcast_ref::<Float64Array>() {
                    format!("{}", a.value(r))
                } else {
                    String::new()
                }
            })
            .collect();
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

/// The study's files in `dir`: `sensitivity.parquet`, `sensitivity.csv` and
/// `sensitivity.svg` (the chart is best effort: its error comes back as a warning).
pub fn write_study(dir: &Path, study: &Study) -> Result<Vec<String>, SensitivityError> {
    let table = long_table(study);
    let p = dir.join("sensitivity.parquet");
    let bytes = parquet_bytes(&table).map_err(|e| io(&p, e))?;
    write_atomic(&p, &bytes)?;
    write_atomic(&dir.join("sensitivity.csv"), csv_text(&table).as_bytes())?;
    let mut warnings = Vec::new();
    if let Err(e) = crate::chart::write_chart(&dir.join("sensitivity.svg"), study) {
        warnings.push(format!("sensitivity.svg not written: {e}"));
    }
    Ok(warnings)
}

/// The files [`write_study`] writes.
pub const STUDY_FILES: &[&str] = &["sensitivity.parquet", "sensitivity.csv", "sensitivity.svg"];
