//! The question's goals in a design file: `[[limit]]` (what every run must meet) and
//! `[objective]` (what the chosen design optimises).

use toml::Value;

use super::{as_number, check_keys, numeric_metrics, tables};
use cushion_model::Summary;

use crate::limits::{Limit, Objective, Sense};

pub(super) fn limits(doc: &toml::Table) -> Result<Vec<Limit>, String> {
    let numeric = numeric_metrics();
    let mut out = Vec::new();
    let list = tables(doc, "limit")?;
    if list.is_empty() {
        return Err("[[limit]]: none given; give at least one (metric with max and/or min)".into());
    }
    for (i, t) in list.into_iter().enumerate() {
        let label = format!("[[limit]] #{}", i + 1);
        check_keys(t, &["metric", "max", "min", "abs"], &label)?;
        let metric = match t.get("metric") {
            Some(Value::String(m)) => m.clone(),
            Some(other) => {
                return Err(format!(
                    "{label}: metric = {other}: a summary field's name (a string)"
                ))
            }
            None => return Err(format!("{label}: missing `metric`")),
        };
        check_metric(&format!("{label}: metric"), &metric, &numeric)?;
        let label = format!("{label} (`{metric}`)");
        let bound = |k: &str| -> Result<Option<f64>, String> {
            match t.get(k) {
                None => Ok(None),
                Some(v) => match as_number(v) {
                    Some(x) if x.is_finite() => Ok(Some(x)),
                    _ => Err(format!("{label}: {k} = {v}: a finite number")),
                },
            }
        };
        let (max, min) = (bound("max")?, bound("min")?);
        if max.is_none() && min.is_none() {
            return Err(format!("{label}: no bound: give max and/or min"));
        }
        if let (Some(max), Some(min)) = (max, min) {
            if min > max {
                return Err(format!("{label}: min = {min}: at most max ({max})"));
            }
        }
        let abs = match t.get("abs") {
            None => false,
            Some(Value::Boolean(b)) => *b,
            Some(other) => return Err(format!("{label}: abs = {other}: true or false")),
        };
        out.push(Limit {
            metric,
            max,
            min,
            abs,
        });
    }
    Ok(out)
}

fn check_metric(what: &str, metric: &str, numeric: &[&str]) -> Result<(), String> {
    if numeric.contains(&metric) {
        return Ok(());
    }
    let kind = if Summary::COLUMNS.contains(&metric) {
        "a numeric summary field (this one is not a number)"
    } else {
        "a numeric summary field"
    };
    Err(format!(
        "{what} = {metric:?}: {kind}; allowed: {}",
        numeric.join(", ")
    ))
}

pub(super) fn objective(doc: &toml::Table) -> Result<Option<Objective>, String> {
    let t = match doc.get("objective") {
        None => return Ok(None),
        Some(Value::Table(t)) => t,
        Some(other) => {
            return Err(format!(
                "`objective` must be a table [objective] with minimize or maximize = \"metric\", got {other}"
            ))
        }
    };
    check_keys(t, &["minimize", "maximize"], "[objective]")?;
    let (sense, key) =
        match (t.get("minimize"), t.get("maximize")) {
            (Some(_), None) => (Sense::Minimize, "minimize"),
            (None, Some(_)) => (Sense::Maximize, "maximize"),
            _ => return Err(
                "[objective]: give exactly one of minimize = \"metric\" or maximize = \"metric\""
                    .into(),
            ),
        };
    let metric = match &t[key] {
        Value::String(m) => m.clone(),
        other => {
            return Err(format!(
                "[objective] {key} = {other}: a summary field's name (a string)"
            ))
        }
    };
    check_metric(&format!("[objective] {key}"), &metric, &numeric_metrics())?;
    let limited = tables(doc, "limit")?
        .iter()
        .any(|l| l.get("metric").and_then(Value::as_str) == Some(metric.as_str()));
    if !limited {
        return Err(format!(
            "[objective] {key} = {metric:?}: a metric that has a [[limit]] (the objective ranks feasible designs)"
        ));
    }
    Ok(Some(Objective { metric, sense }))
}
