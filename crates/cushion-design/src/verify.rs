//! The chosen design verified: run on a fine grid of the `for_all` box (`n` points per range,
//! every value of each list), independent of the search that chose it, and judged run by run.

use crate::axes::{Axes, Point};
use crate::error::{config, DesignError};
use crate::grid::Grid;
use crate::limits::Limits;
use crate::metrics::{failed, Worst};

/// The most runs a verification grid may have.
const MAX_VERIFY: usize = 10_000_000;

/// The `for_all` points of the verification grid, in real units (first axis slowest).
pub fn verify_grid(for_all: &Axes, n: usize) -> Result<Vec<Point>, DesignError> {
    if n < 2 {
        return Err(config("search.verify", n, "at least 2 points per range"));
    }
    Grid::check_size(for_all, n, "search.verify", MAX_VERIFY)?;
    Ok(Grid::new(for_all, n)
        .points()
        .iter()
        .map(|c| for_all.real(c))
        .collect())
}

/// What the verification grid says about a design.
#[derive(Clone, Debug, PartialEq)]
pub struct Verification {
    /// Every run met every limit.
    pub all_met: bool,
    /// Runs that missed a limit (failed runs included).
    pub violations: usize,
    /// Runs that failed.
    pub failed: usize,
    /// Per target of [`Limits::targets`], the worst case on the grid (the first failed run, if
    /// one failed).
    pub worst: Vec<Worst>,
    /// The margin of those worst cases.
    pub margin: f64,
    pub runs: usize,
}

/// Judge the rows of the runs at `points` (one row per point, one value per metric).
pub fn check(
    limits: &Limits,
    points: &[Point],
    rows: &[Vec<f64>],
) -> Result<Verification, DesignError> {
    let m = limits.metrics().len();
    if rows.len() != points.len() || rows.iter().any(|r| r.len() != m) {
        return Err(DesignError::Protocol(format!(
            "check: {} rows for {} points, each needs {m} values",
            rows.len(),
            points.len()
        )));
    }
    if points.is_empty() {
        return Err(DesignError::Protocol("check: no runs to verify".into()));
    }
    let first_failed = rows.iter().position(|r| failed(r));
    let worst = limits
        .targets()
        .iter()
        .map(|t| {
            if let Some(k) = first_failed {
                return Worst {
                    value: f64::NAN,
                    witness: points[k].clone(),
                    failed: true,
                };
            }
            let mut k = 0;
            for (i, r) in rows.iter().enumerate() {
                if t.direction.badness(r[t.metric]) > t.direction.badness(rows[k][t.metric]) {
                    k = i;
                }
            }
            Worst {
                value: rows[k][t.metric],
                witness: points[k].clone(),
                failed: false,
            }
        })
        .collect::<Vec<_>>();
    let violations = rows.iter().filter(|r| !limits.meets(r)).count();
    Ok(Verification {
        all_met: violations == 0,
        violations,
        failed: rows.iter().filter(|r| failed(r)).count(),
        margin: limits.judge(&worst).margin,
        worst,
        runs: rows.len(),
    })
}
