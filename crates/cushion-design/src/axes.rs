//! The boxes a design question is asked over: the `for_all` box (the conditions a design must
//! survive) and the design axes (what the designer chooses). Both are lists of axes, each a
//! continuous range (linear or log scale) or a list of values.
//!
//! The search works in normalised coordinates: a continuous axis maps `[low, high]` onto
//! `[0, 1]` (uniformly in the logarithm on a log scale), a list axis is the index of its value
//! (`0.0, 1.0, ...`). A [`Point`] in real units holds the real value of a continuous axis and the
//! index of a list axis; the caller maps indices to its own values (numbers or strings).

use crate::error::{config, DesignError};

/// One point of a box in real units: one value per axis, the index of the value for a list axis.
pub type Point = Vec<f64>;

/// How a continuous axis is spread between its ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    /// Uniform in the logarithm: for quantities that span decades (orifices, stiffnesses).
    Log,
}

/// What values an axis takes.
#[derive(Clone, Debug, PartialEq)]
pub enum AxisKind {
    /// Every value in `[low, high]`.
    Range { low: f64, high: f64, scale: Scale },
    /// `count` separate values, known here by their index (unordered: a module name is as good
    /// as a number).
    Values { count: usize },
}

/// One axis: its key (for messages) and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub key: String,
    pub kind: AxisKind,
}

impl Axis {
    /// A continuous axis on a linear scale.
    pub fn range(key: &str, low: f64, high: f64) -> Axis {
        Axis::with_kind(
            key,
            AxisKind::Range {
                low,
                high,
                scale: Scale::Linear,
            },
        )
    }

    /// A continuous axis on a log scale.
    pub fn log_range(key: &str, low: f64, high: f64) -> Axis {
        Axis::with_kind(
            key,
            AxisKind::Range {
                low,
                high,
                scale: Scale::Log,
            },
        )
    }

    /// A list axis of `count` values.
    pub fn values(key: &str, count: usize) -> Axis {
        Axis::with_kind(key, AxisKind::Values { count })
    }

    fn with_kind(key: &str, kind: AxisKind) -> Axis {
        Axis {
            key: key.to_string(),
            kind,
        }
    }

    /// Whether the axis is a continuous range (and so searched and split); a list axis is
    /// taken value by value.
    pub fn is_continuous(&self) -> bool {
        matches!(self.kind, AxisKind::Range { .. })
    }

    fn check(&self) -> Result<(), DesignError> {
        match self.kind {
            AxisKind::Range { low, high, scale } => {
                let value = format!("[{low}, {high}]");
                if !(low.is_finite() && high.is_finite() && low < high) {
                    return Err(config(
                        format!("{}.range", self.key),
                        value,
                        "two finite numbers with low < high",
                    ));
                }
                if scale == Scale::Log && low <= 0.0 {
                    return Err(config(
                        format!("{}.range", self.key),
                        value,
                        "a log scale needs low > 0",
                    ));
                }
                Ok(())
            }
            AxisKind::Values { count: 0 } => Err(config(
                format!("{}.values", self.key),
                "[]",
                "at least one value",
            )),
            AxisKind::Values { .. } => Ok(()),
        }
    }

    /// The real value at normalised coordinate `c`. The ends are returned exactly, so a
    /// witness on the edge of the box is the edge's value to the bit.
    pub fn real(&self, c: f64) -> f64 {
        match self.kind {
            AxisKind::Range { low, high, scale } => {
                if c <= 0.0 {
                    low
                } else if c >= 1.0 {
                    high
                } else {
                    match scale {
                        Scale::Linear => (1.0 - c) * low + c * high,
                        Scale::Log => ((1.0 - c) * low.ln() + c * high.ln()).exp(),
                    }
                }
            }
            AxisKind::Values { .. } => c,
        }
    }

    /// The normalised coordinate of a real value; an error when it lies outside the axis.
    pub fn coordinate(&self, v: f64) -> Result<f64, DesignError> {
        match self.kind {
            AxisKind::Range { low, high, scale } => {
                if !(v >= low && v <= high) {
                    return Err(config(&self.key, v, format!("a value in [{low}, {high}]")));
                }
                Ok(match scale {
                    Scale::Linear => (v - low) / (high - low),
                    Scale::Log => (v / low).ln() / (high / low).ln(),
                }
                .clamp(0.0, 1.0))
            }
            AxisKind::Values { count } => {
                if v.fract() != 0.0 || !(v >= 0.0 && v < count as f64) {
                    return Err(config(
                        &self.key,
                        v,
                        format!(
                            "the index of one of its {count} values (0 to {})",
                            count - 1
                        ),
                    ));
                }
                Ok(v)
            }
        }
    }

    /// The normalised coordinates of a grid along this axis: `n` evenly spaced points (ends
    /// included) of a range, every index of a list.
    pub(crate) fn grid(&self, n: usize) -> Vec<f64> {
        match self.kind {
            AxisKind::Range { .. } if n <= 1 => vec![0.5],
            AxisKind::Range { .. } => (0..n).map(|i| i as f64 / (n - 1) as f64).collect(),
            AxisKind::Values { count } => (0..count).map(|i| i as f64).collect(),
        }
    }
}

/// A box: one or more axes with distinct keys.
#[derive(Clone, Debug, PartialEq)]
pub struct Axes {
    axes: Vec<Axis>,
}

impl Axes {
    /// Check the axes: at least one, keys distinct, each range finite with low < high (and
    /// low > 0 on a log scale), each list not empty. `what` names the box in messages
    /// (`"for_all"`, `"design"`).
    pub fn new(what: &str, axes: Vec<Axis>) -> Result<Axes, DesignError> {
        if axes.is_empty() {
            return Err(config(what, "[]", "at least one axis"));
        }
        for (i, a) in axes.iter().enumerate() {
            a.check()?;
            if axes[..i].iter().any(|b| b.key == a.key) {
                return Err(config(what, &a.key, "each key once"));
            }
        }
        Ok(Axes { axes })
    }

    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    pub fn len(&self) -> usize {
        self.axes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.axes.is_empty()
    }

    /// The point in real units at normalised coordinates `c`.
    pub fn real(&self, c: &[f64]) -> Point {
        self.axes.iter().zip(c).map(|(a, &c)| a.real(c)).collect()
    }

    /// The normalised coordinates of a point in real units; an error names the axis that the
    /// point leaves.
    pub fn coordinates(&self, p: &[f64]) -> Result<Vec<f64>, DesignError> {
        if p.len() != self.axes.len() {
            return Err(config(
                "point",
                format!("{} values", p.len()),
                format!("one value per axis ({})", self.axes.len()),
            ));
        }
        self.axes
            .iter()
            .zip(p)
            .map(|(a, &v)| a.coordinate(v))
            .collect()
    }
}
