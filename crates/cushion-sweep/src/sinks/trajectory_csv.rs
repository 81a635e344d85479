//! One run's trajectory as CSV (the columns of `docs/model.md`, section "Summary fields").
//!
//! Header: [`TrajectoryPoint::COLUMNS`] (`t,x_r,v_r,x_t,v_t,x_p,v_p,s,p1,F_c,F_r`), SI units
//! (s, m, m/s, Pa, N). One row per recorded point, in time order. Numbers are written in the
//! shortest form that reads back to the same `f64` bit for bit; a quantity the scene does not
//! have (no object, no gas: NaN in the trajectory) is an empty cell.
//!
//! Files are written atomically: to a temporary file beside the target, then renamed, so no
//! partial file ever exists under the final name.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use cushion_model::{Trajectory, TrajectoryPoint};

use crate::atomic::AtomicFile;

/// Write `trajectory` as CSV to `path` (atomically).
pub fn write_csv(path: &Path, trajectory: &Trajectory) -> io::Result<()> {
    write_atomically(path, |w| write_csv_to(w, trajectory))
}

/// Write `trajectory` as CSV to any writer (header, then one row per point).
pub fn write_csv_to<W: Write>(w: &mut W, trajectory: &Trajectory) -> io::Result<()> {
    writeln!(w, "{}", TrajectoryPoint::COLUMNS.join(","))?;
    let mut cell = String::with_capacity(32);
    for p in &trajectory.points {
        for (i, v) in p.values().iter().enumerate() {
            if i > 0 {
                w.write_all(b",")?;
            }
            cell.clear();
            push_number(&mut cell, *v);
            w.write_all(cell.as_bytes())?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// Append `v` in the shortest text that parses back to the same `f64` (Rust's float formatting
/// is shortest-round-trip): plain decimals for ordinary magnitudes, `1.5e-7` style otherwise.
/// NaN appends nothing (an empty cell); infinities are `inf` / `-inf`.
pub fn push_number(out: &mut String, v: f64) {
    use std::fmt::Write as _;
    if v.is_nan() {
        return;
    }
    let a = v.abs();
    if a == 0.0 || (1e-4..1e15).contains(&a) || a.is_infinite() {
        let _ = write!(out, "{v}");
    } else {
        let _ = write!(out, "{v:e}");
    }
}

/// Write a file atomically with [`crate::atomic::AtomicFile`]: `fill` writes into a temporary
/// file beside `path`, which is then synced and renamed onto `path`. On any error the
/// temporary file is removed and `path` is left as it was.
pub(crate) fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    fill(file.writer())?;
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t: f64) -> TrajectoryPoint {
        TrajectoryPoint {
            t,
            x_r: t * 1.0,
            v_r: 1.0,
            x_t: 0.1 + t,
            v_t: 0.3 / 7.0,
            x_p: f64::NAN,
            v_p: f64::NAN,
            s: -1.23456789012345e-7,
            p1: 1000.0 + t,
            f_c: 0.0,
            f_r: -12.5,
        }
    }

    fn parse_csv(text: &str) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
        let mut lines = text.lines();
        let header = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|c| {
                        if c.is_empty() {
                            None
                        } else {
                            Some(c.parse::<f64>().unwrap())
                        }
                    })
                    .collect()
            })
            .collect();
        (header, rows)
    }

    #[test]
    fn header_rows_and_exact_values() {
        let traj = Trajectory {
            points: vec![point(0.0), point(1.0 / 3.0), point(0.3)],
        };
        let mut buf = Vec::new();
        write_csv_to(&mut buf, &traj).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let (header, rows) = parse_csv(&text);
        assert_eq!(header, TrajectoryPoint::COLUMNS.to_vec());
        assert_eq!(rows.len(), 3);
        for (row, p) in rows.iter().zip(&traj.points) {
            assert_eq!(row.len(), 11);
            for (cell, v) in row.iter().zip(p.values()) {
                match cell {
                    None => assert!(v.is_nan()),
                    // bit-exact round trip
                    Some(c) => assert_eq!(c.to_bits(), v.to_bits()),
                }
            }
        }
        // NaN columns are empty cells
        assert!(text.lines().nth(1).unwrap().contains(",,"));
    }

    #[test]
    fn numbers_round_trip() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-4,
            9.99e-5,
            1e-300,
            5e-324,
            1e15,
            123456.789,
            f64::MAX,
        ] {
            let mut s = String::new();
            push_number(&mut s, v);
            assert_eq!(
                s.parse::<f64>().unwrap().to_bits(),
                v.to_bits(),
                "{v} -> {s}"
            );
        }
        let mut s = String::new();
        push_number(&mut s, f64::NAN);
        assert!(s.is_empty());
    }

    #[test]
    fn atomic_write_leaves_no_temp_and_no_partial_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("traj.csv");
        write_csv(
            &path,
            &Trajectory {
                points: vec![point(0.0)],
            },
        )
        .unwrap();
        assert!(path.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

        // A failing fill leaves neither the target nor a temp file.
        let path2 = dir.path().join("bad.csv");
        let err = write_atomically(&path2, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        });
        assert!(err.is_err());
        assert!(!path2.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
