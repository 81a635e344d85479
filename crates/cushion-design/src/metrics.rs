//! What the search looks for: for each limited metric, which end of its values over the
//! `for_all` box is the worst case, and the worst case found with its witness.
//!
//! The caller tells the values of a run as one row: one number per metric, in the order of
//! [`crate::Limits::metrics`]. A run failed when any number of its row is not finite; the caller
//! passes `f64::NAN` for every metric of a run whose status is not `ok`. A failed run violates
//! every limit.

use crate::axes::Point;

/// Which end of a metric's values is its worst case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// The largest value (a `max` limit).
    Max,
    /// The smallest value (a `min` limit).
    Min,
    /// The largest size `|value|` (a `max` limit with `abs`: a signed peak force).
    AbsMax,
    /// The smallest size `|value|` (a `min` limit with `abs`).
    AbsMin,
}

impl Direction {
    /// How bad a value is, larger being worse: the one number the search maximises.
    pub(crate) fn badness(self, v: f64) -> f64 {
        match self {
            Direction::Max => v,
            Direction::Min => -v,
            Direction::AbsMax => v.abs(),
            Direction::AbsMin => -v.abs(),
        }
    }

    /// The quantity a limit judges: the value, or its size for the `abs` directions.
    pub fn size(self, v: f64) -> f64 {
        match self {
            Direction::Max | Direction::Min => v,
            Direction::AbsMax | Direction::AbsMin => v.abs(),
        }
    }
}

/// One worst case to search for: a metric (its column in a run's row) and its direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Target {
    pub metric: usize,
    pub direction: Direction,
}

/// The worst case found for one target at one design point.
#[derive(Clone, Debug, PartialEq)]
pub struct Worst {
    /// The metric's value at the witness, as the run gave it (signed, also for an `abs`
    /// direction), so that running the witness again gives this number to the bit. `NaN` when
    /// the worst case is a failed run.
    pub value: f64,
    /// The `for_all` point, in real units, where it happens.
    pub witness: Point,
    /// The worst case is a failed run (it violates every limit).
    pub failed: bool,
}

/// Whether a run's row says it failed: any metric not finite.
pub(crate) fn failed(row: &[f64]) -> bool {
    row.iter().any(|v| !v.is_finite())
}
