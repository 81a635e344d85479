//! The limits a design must meet over the whole `for_all` box, the optional objective, and the
//! judgement of a design point by its worst cases: feasible or not, and by what margin.
//!
//! The margin is the smallest relative distance of the worst cases to their limits:
//! `(max - worst) / |max|` for a `max` limit, `(worst - min) / |min|` for a `min` limit (the
//! distance itself when the limit is 0, which has no scale), with `|worst|` for an `abs` limit.
//! It is negative when a limit is violated, and `-inf` when a worst case is a failed run. A
//! design point is feasible when its margin is at least 0.

use crate::error::{config, DesignError};
use crate::metrics::{failed, Direction, Target, Worst};

/// One limit on one metric: `max` and/or `min`, on the value or (with `abs`) on its size.
#[derive(Clone, Debug, PartialEq)]
pub struct Limit {
    pub metric: String,
    pub max: Option<f64>,
    pub min: Option<f64>,
    pub abs: bool,
}

impl Limit {
    /// `metric <= max`.
    pub fn max(metric: &str, max: f64) -> Limit {
        Limit {
            metric: metric.to_string(),
            max: Some(max),
            min: None,
            abs: false,
        }
    }

    /// `metric >= min`.
    pub fn min(metric: &str, min: f64) -> Limit {
        Limit {
            metric: metric.to_string(),
            max: None,
            min: Some(min),
            abs: false,
        }
    }

    /// The same limit on the size `|metric|`.
    pub fn abs(self) -> Limit {
        Limit { abs: true, ..self }
    }
}

/// Whether the objective wants the worst case small or large.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    /// Minimize the largest value over the `for_all` box.
    Minimize,
    /// Maximize the smallest value over the `for_all` box.
    Maximize,
}

/// Among the feasible designs, the one whose worst case of `metric` is best.
#[derive(Clone, Debug, PartialEq)]
pub struct Objective {
    pub metric: String,
    pub sense: Sense,
}

/// One bound of one limit, on one target's worst case.
#[derive(Clone, Debug, PartialEq)]
struct Bound {
    target: usize,
    value: f64,
    upper: bool,
}

/// The limits of a design question, checked, with the targets their worst cases need.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits {
    metrics: Vec<String>,
    targets: Vec<Target>,
    bounds: Vec<Bound>,
    objective: Option<(Sense, usize)>,
}

/// A design point judged by its worst cases.
#[derive(Clone, Debug, PartialEq)]
pub struct Judgement {
    /// Every worst case meets every limit (none is a failed run).
    pub feasible: bool,
    /// The smallest relative distance to a limit (see the module docs).
    pub margin: f64,
    /// The objective's worst case (its size for an `abs` limit); `NaN` if that is a failed run.
    pub objective: Option<f64>,
}

impl Limits {
    /// Check the limits and the objective: at least one limit, each with a finite `max` or
    /// `min`, `min <= max`, `max >= 0` with `abs`, the objective on a limited metric.
    pub fn new(limits: Vec<Limit>, objective: Option<Objective>) -> Result<Limits, DesignError> {
        if limits.is_empty() {
            return Err(config("limit", "[]", "at least one limit"));
        }
        let mut out = Limits {
            metrics: Vec::new(),
            targets: Vec::new(),
            bounds: Vec::new(),
            objective: None,
        };
        for l in &limits {
            check(l)?;
            let metric = out.metric(&l.metric);
            let (up, down) = if l.abs {
                (Direction::AbsMax, Direction::AbsMin)
            } else {
                (Direction::Max, Direction::Min)
            };
            for (bound, direction, upper) in [(l.max, up, true), (l.min, down, false)] {
                if let Some(value) = bound {
                    let target = out.target(Target { metric, direction });
                    out.bounds.push(Bound {
                        target,
                        value,
                        upper,
                    });
                }
            }
        }
        if let Some(o) = objective {
            // The objective is on a metric the user limited, so its column is already asked for;
            // `abs` follows the first limit on it.
            let Some(l) = limits.iter().find(|l| l.metric == o.metric) else {
                return Err(config(
                    "objective",
                    &o.metric,
                    "a metric that has a [[limit]]",
                ));
            };
            let direction = match (o.sense, l.abs) {
                (Sense::Minimize, false) => Direction::Max,
                (Sense::Minimize, true) => Direction::AbsMax,
                (Sense::Maximize, false) => Direction::Min,
                (Sense::Maximize, true) => Direction::AbsMin,
            };
            let metric = out.metric(&o.metric);
            let target = out.target(Target { metric, direction });
            out.objective = Some((o.sense, target));
        }
        Ok(out)
    }

    fn metric(&mut self, name: &str) -> usize {
        match self.metrics.iter().position(|m| m == name) {
            Some(i) => i,
            None => {
                self.metrics.push(name.to_string());
                self.metrics.len() - 1
            }
        }
    }

    fn target(&mut self, t: Target) -> usize {
        match self.targets.iter().position(|&u| u == t) {
            Some(i) => i,
            None => {
                self.targets.push(t);
                self.targets.len() - 1
            }
        }
    }

    /// The metrics a run must report, in the order of its row.
    pub fn metrics(&self) -> &[String] {
        &self.metrics
    }

    /// The worst cases to search for, in the order of every `worst` list.
    pub fn targets(&self) -> &[Target] {
        &self.targets
    }

    /// The objective: its sense and the index of its target, if there is one.
    pub fn objective(&self) -> Option<(Sense, usize)> {
        self.objective
    }

    /// Judge a design point by its worst cases (one per target, in order).
    pub fn judge(&self, worst: &[Worst]) -> Judgement {
        let objective = self.objective.map(|(_, t)| {
            let w = &worst[t];
            if w.failed {
                f64::NAN
            } else {
                self.targets[t].direction.size(w.value)
            }
        });
        if worst.iter().any(|w| w.failed) {
            return Judgement {
                feasible: false,
                margin: f64::NEG_INFINITY,
                objective,
            };
        }
        let margin = self
            .bounds
            .iter()
            .map(|b| {
                let size = self.targets[b.target].direction.size(worst[b.target].value);
                distance(b, size)
            })
            .fold(f64::INFINITY, f64::min);
        Judgement {
            feasible: margin >= 0.0,
            margin,
            objective,
        }
    }

    /// Whether one run (its row of metric values) meets every limit.
    pub fn meets(&self, row: &[f64]) -> bool {
        !failed(row)
            && self.bounds.iter().all(|b| {
                let t = self.targets[b.target];
                distance(b, t.direction.size(row[t.metric])) >= 0.0
            })
    }
}

/// The relative distance of `size` inside bound `b` (negative outside).
fn distance(b: &Bound, size: f64) -> f64 {
    let scale = if b.value == 0.0 { 1.0 } else { b.value.abs() };
    let d = if b.upper {
        b.value - size
    } else {
        size - b.value
    };
    d / scale
}

fn check(l: &Limit) -> Result<(), DesignError> {
    let key = |k: &str| format!("limit.{}.{k}", l.metric);
    if l.max.is_none() && l.min.is_none() {
        return Err(config(
            format!("limit.{}", l.metric),
            "no bound",
            "max and/or min",
        ));
    }
    for (name, v) in [("max", l.max), ("min", l.min)] {
        if let Some(v) = v.filter(|v| !v.is_finite()) {
            return Err(config(key(name), v, "a finite number"));
        }
    }
    if let (Some(max), Some(min)) = (l.max, l.min) {
        if min > max {
            return Err(config(key("min"), min, format!("at most max ({max})")));
        }
    }
    if let Some(max) = l.max.filter(|&m| l.abs && m < 0.0) {
        return Err(config(
            key("max"),
            max,
            "at least 0 with abs = true (a size is never negative)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn worst(value: f64) -> Worst {
        Worst {
            value,
            witness: vec![0.0],
            failed: false,
        }
    }

    #[test]
    fn margin_is_the_smallest_relative_distance() {
        let limits = Limits::new(
            vec![Limit::max("force", 40.0).abs(), Limit::max("speed", 1.3)],
            None,
        )
        .unwrap();
        assert_eq!(limits.metrics(), ["force", "speed"]);
        // Force -36 N: 10 % under 40 N; speed 1.17 m/s: 10 % under too; speed 1.235: 5 %.
        let j = limits.judge(&[worst(-36.0), worst(1.235)]);
        assert!(j.feasible);
        assert!((j.margin - 0.05).abs() < 1e-12);
        let j = limits.judge(&[worst(-44.0), worst(1.0)]);
        assert!(!j.feasible);
        assert!((j.margin + 0.1).abs() < 1e-12);
        let failed = Worst {
            value: f64::NAN,
            witness: vec![0.0],
            failed: true,
        };
        let j = limits.judge(&[worst(1.0), failed]);
        assert!(!j.feasible && j.margin == f64::NEG_INFINITY);
        assert!(limits.meets(&[-39.0, 1.3]) && !limits.meets(&[41.0, 1.0]));
        assert!(!limits.meets(&[1.0, f64::NAN]));
    }

    #[test]
    fn max_and_min_of_one_metric_need_two_targets_and_the_objective_shares_one() {
        let mut l = Limit::max("x", 2.0);
        l.min = Some(-1.0);
        let limits = Limits::new(
            vec![l],
            Some(Objective {
                metric: "x".into(),
                sense: Sense::Minimize,
            }),
        )
        .unwrap();
        assert_eq!(limits.targets().len(), 2);
        assert_eq!(limits.objective(), Some((Sense::Minimize, 0)));
        let j = limits.judge(&[worst(1.5), worst(-0.5)]);
        assert_eq!(j.objective, Some(1.5));
        // The limit 0 has no scale: the distance itself.
        let zero = Limits::new(vec![Limit::min("y", 0.0)], None).unwrap();
        assert_eq!(zero.judge(&[worst(-0.25)]).margin, -0.25);
    }

    #[test]
    fn bad_limits_name_the_key() {
        let mut l = Limit::max("x", 1.0);
        l.min = Some(2.0);
        let e = Limits::new(vec![l], None).unwrap_err();
        assert_eq!(e.to_string(), "limit.x.min = 2: at most max (1)");
        let e = Limits::new(vec![Limit::max("x", -1.0).abs()], None).unwrap_err();
        assert!(e.to_string().starts_with("limit.x.max = -1"));
        let o = Objective {
            metric: "y".into(),
            sense: Sense::Maximize,
        };
        let e = Limits::new(vec![Limit::max("x", 1.0)], Some(o)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "objective = y: a metric that has a [[limit]]"
        );
        assert!(Limits::new(vec![], None).is_err());
        assert!(Limits::new(vec![Limit::max("x", f64::NAN)], None).is_err());
    }
}
