//! One `[[axis]]` of a sweep file: its key and its values (`values`, `linspace`, `logspace`,
//! `range` with `scale` or a distribution `dist`), checked against the sampling mode.

use super::toml_helpers::{as_number, check_keys, type_name};
use super::*;
use cushion_sensitivity::{Distribution, Domain, Marginal};

/// `(start, stop, n)` of a linspace/logspace array.
fn spaced(key: &str, form: &str, v: &Value) -> Result<(f64, f64, usize), String> {
    let arr = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| format!("{key}: `{form}` must be [start, stop, n], got {v}"))?;
    let start = as_number(&arr[0])
        .ok_or_else(|| format!("{key}: `{form}` start must be a number, got {}", arr[0]))?;
    let stop = as_number(&arr[1])
        .ok_or_else(|| format!("{key}: `{form}` stop must be a number, got {}", arr[1]))?;
    let n = match &arr[2] {
        Value::Integer(n) => *n,
        other => {
            return Err(format!(
                "{key}: `{form}` n must be an integer >= 1, got {other}"
            ))
        }
    };
    if n < 1 {
        return Err(format!(
            "{key}: `{form}` n must be an integer >= 1, got {n}"
        ));
    }
    if n as u64 > MAX_RUNS {
        return Err(format!(
            "{key}: `{form}` n = {n} is too large (at most {MAX_RUNS})"
        ));
    }
    if !start.is_finite() || !stop.is_finite() {
        return Err(format!(
            "{key}: `{form}` start and stop must be finite, got {v}"
        ));
    }
    Ok((start, stop, n as usize))
}

/// `n` evenly spaced values from `start` to `stop`, both included; exact at the ends.
pub fn linspace(start: f64, stop: f64, n: usize) -> Vec<f64> {
    if n == 1 {
        return vec![start];
    }
    (0..n)
        .map(|i| {
            if i == n - 1 {
                stop
            } else {
                start + (stop - start) * (i as f64) / ((n - 1) as f64)
            }
        })
        .collect()
}

/// `n` values evenly spaced in log from `start` to `stop` (endpoints, both > 0, both included).
pub fn logspace(start: f64, stop: f64, n: usize) -> Vec<f64> {
    let (a, b) = (start.ln(), stop.ln());
    linspace(a, b, n)
        .into_iter()
        .enumerate()
        .map(|(i, x)| {
            if i == 0 {
                start
            } else if i == n - 1 {
                stop
            } else {
                x.exp()
            }
        })
        .collect()
}

/// The distribution keys of a `range` axis, besides `range` and `scale`.
const DIST_KEYS: &[&str] = &["dist", "mean", "sd", "median", "sigma", "mode"];

/// The distribution an axis asks for (`dist` and its parameters), checked against its range.
/// `None` for a uniform or loguniform axis, which the sampler maps as it always has.
fn parse_dist(
    t: &toml::Table,
    label: &str,
    key: &str,
    range: Option<(f64, f64)>,
    base: &Scene,
) -> Result<Option<Marginal>, String> {
    let (name, wants) = dist_name_and_params(t, label)?;
    check_no_other_params(t, label, name, wants)?;
    let Some(dist) = distribution(t, label, name, wants, range)? else {
        return Ok(None);
    };
    // A key the scene refuses below zero (a mass, a radius, a pressure, a time) cannot take
    // an untruncated normal: some of its draws would be negative.
    let domain = if range.is_none() && refuses_negative(base, key) {
        Domain::Positive
    } else {
        Domain::Real
    };
    let range = match dist {
        Distribution::Triangular { .. } => None,
        _ => range,
    };
    Marginal::new(key, dist, range, domain)
        .map(Some)
        .map_err(|e| format!("{label}: {e}"))
}

/// The name of the axis's distribution (`uniform` when it gives none) and the parameters that
/// distribution takes.
fn dist_name_and_params<'t>(
    t: &'t toml::Table,
    label: &str,
) -> Result<(&'t str, &'static [&'static str]), String> {
    let name = match t.get("dist") {
        None => "uniform",
        Some(Value::String(s)) => s.as_str(),
        Some(other) => {
            return Err(format!(
                "{label}: dist = {other}: allowed \"uniform\", \"loguniform\", \"normal\", \"lognormal\", \"triangular\""
            ))
        }
    };
    let wants: &[&str] = match name {
        "uniform" | "loguniform" => &[],
        "normal" => &["mean", "sd"],
        "lognormal" => &["median", "sigma"],
        "triangular" => &["mode"],
        other => {
            return Err(format!(
                "{label}: dist = {other:?}: allowed \"uniform\", \"loguniform\", \"normal\", \"lognormal\", \"triangular\""
            ))
        }
    };
    Ok((name, wants))
}

/// No parameter of another distribution than `name`.
fn check_no_other_params(
    t: &toml::Table,
    label: &str,
    name: &str,
    wants: &[&str],
) -> Result<(), String> {
    for k in &DIST_KEYS[1..] {
        if t.contains_key(*k) && !wants.contains(k) {
            return Err(format!(
                "{label}: `{k}` does not go with dist = \"{name}\" (it takes {})",
                if wants.is_empty() {
                    "no parameter but `range`".to_string()
                } else {
                    wants
                        .iter()
                        .map(|w| format!("`{w}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                }
            ));
        }
    }
    Ok(())
}

/// The distribution `name` with its parameters read from the axis; `None` for uniform and
/// loguniform.
fn distribution(
    t: &toml::Table,
    label: &str,
    name: &str,
    wants: &[&str],
    range: Option<(f64, f64)>,
) -> Result<Option<Distribution>, String> {
    let param = |k: &str| -> Result<f64, String> {
        match t.get(k) {
            None => Err(format!(
                "{label}: dist = \"{name}\" needs `{k}` (it takes {})",
                wants
                    .iter()
                    .map(|w| format!("`{w}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            Some(v) => as_number(v).ok_or_else(|| format!("{label}: {k} = {v}: must be a number")),
        }
    };
    let need_range =
        || range.ok_or_else(|| format!("{label}: dist = \"{name}\" needs `range = [low, high]`"));
    let dist = match name {
        "uniform" | "loguniform" => return Ok(None),
        "normal" => Distribution::Normal {
            mean: param("mean")?,
            sd: param("sd")?,
        },
        "lognormal" => Distribution::LogNormal {
            median: param("median")?,
            sigma: param("sigma")?,
        },
        _ => {
            let (low, high) = need_range()?;
            Distribution::Triangular {
                low,
                mode: param("mode")?,
                high,
            }
        }
    };
    Ok(Some(dist))
}

/// Whether the scene refuses a negative value of `key` (probed on the sweep's base scene).
fn refuses_negative(base: &Scene, key: &str) -> bool {
    let mut probe = base.clone();
    if probe.set(key, &Value::Float(-1.0)).is_err() {
        return true;
    }
    match probe.validate() {
        Ok(()) => false,
        Err(e) => e.to_string().contains(key),
    }
}

/// Parse `[[axis]]` number `i` (0-based); with its distribution when it has one beyond
/// uniform and loguniform.
pub(super) fn parse_axis(
    i: usize,
    v: &Value,
    mode: Mode,
    base: &Scene,
) -> Result<(Axis, Option<Marginal>), String> {
    let (t, key) = axis_table_and_key(i, v)?;
    let label = format!("[[axis]] #{} (`{key}`)", i + 1);
    check_axis_keys(t, &key, &label)?;
    let form = axis_form(t, &label, mode)?;
    let (values, marginal) = match form {
        "values" | "linspace" | "logspace" => (listed_values(t, &label, form)?, None),
        _ => range_values(t, &label, &key, form, mode, base)?,
    };
    let kind = axis_kind(&values, &label)?;
    Ok((Axis { key, values, kind }, marginal))
}

/// The axis as a table, and its scene key.
fn axis_table_and_key(i: usize, v: &Value) -> Result<(&toml::Table, String), String> {
    let t = v
        .as_table()
        .ok_or_else(|| format!("[[axis]] #{}: must be a table with `key` and values", i + 1))?;
    let key = match t.get("key") {
        Some(Value::String(k)) => k.clone(),
        Some(other) => {
            return Err(format!(
                "[[axis]] #{}: `key` must be a string, got {other}",
                i + 1
            ))
        }
        None => return Err(format!("[[axis]] #{}: missing `key`", i + 1)),
    };
    Ok((t, key))
}

/// Only keys an axis takes, and a key the scene has.
fn check_axis_keys(t: &toml::Table, key: &str, label: &str) -> Result<(), String> {
    let mut allowed = vec!["key", "values", "linspace", "logspace", "range", "scale"];
    allowed.extend_from_slice(DIST_KEYS);
    check_keys(t, &allowed, label)?;
    if !Scene::keys().contains(&key) {
        return Err(format!(
            "{label}: unknown scene key `{key}` (allowed: {})",
            Scene::keys().join(", ")
        ));
    }
    Ok(())
}

/// How the axis gives its values: `values`, `linspace`, `logspace`, `range`, or `dist` (a
/// normal or lognormal without a range); exactly one, with only the keys that go with it and
/// allowed by the sampling mode.
fn axis_form(t: &toml::Table, label: &str, mode: Mode) -> Result<&'static str, String> {
    let mut forms: Vec<&'static str> = ["values", "linspace", "logspace", "range"]
        .into_iter()
        .filter(|f| t.contains_key(*f))
        .collect();
    // A normal or lognormal needs no range: its distribution is the axis.
    let unbounded_dist = matches!(
        t.get("dist").and_then(Value::as_str),
        Some("normal") | Some("lognormal")
    );
    if forms.is_empty() && unbounded_dist {
        forms.push("dist");
    }
    if let (true, Some(d)) = (forms.is_empty(), t.get("dist")) {
        return Err(format!(
            "{label}: dist = {d} needs `range = [low, high]` (only a normal or lognormal may go without)"
        ));
    }
    if forms.len() != 1 {
        return Err(format!(
            "{label}: give exactly one of `values`, `linspace`, `logspace`, `range` (found {})",
            if forms.is_empty() {
                "none".to_string()
            } else {
                forms.join(", ")
            }
        ));
    }
    let form = forms[0];
    if t.contains_key("scale") && form != "range" {
        return Err(format!("{label}: `scale` goes with `range` only"));
    }
    if form != "range" && form != "dist" {
        if let Some(k) = DIST_KEYS.iter().find(|k| t.contains_key(**k)) {
            return Err(format!(
                "{label}: `{k}` goes with a `range` axis only (this axis has `{form}`)"
            ));
        }
        if mode == Mode::Saltelli {
            return Err(format!(
                "{label}: a saltelli sweep takes only `range` axes of numbers (this axis has `{form}`); give it a `range`, or fix its value in [set]"
            ));
        }
    }
    Ok(form)
}

/// The values of a `values`, `linspace` or `logspace` axis.
fn listed_values(t: &toml::Table, label: &str, form: &str) -> Result<AxisValues, String> {
    let values = match form {
        "values" => {
            let arr = t["values"]
                .as_array()
                .ok_or_else(|| format!("{label}: `values` must be an array"))?;
            if arr.is_empty() {
                return Err(format!("{label}: `values` is empty"));
            }
            AxisValues::List(arr.clone())
        }
        "linspace" => {
            let (a, b, n) = spaced(label, "linspace", &t["linspace"])?;
            AxisValues::List(linspace(a, b, n).into_iter().map(Value::Float).collect())
        }
        _ => {
            let (a, b, n) = spaced(label, "logspace", &t["logspace"])?;
            if a <= 0.0 || b <= 0.0 {
                return Err(format!(
                    "{label}: `logspace` takes endpoints (not exponents), both > 0, got [{a}, {b}, {n}]"
                ));
            }
            AxisValues::List(logspace(a, b, n).into_iter().map(Value::Float).collect())
        }
    };
    Ok(values)
}

/// A `range` axis (or a `dist` one, which takes its distribution's support as its range):
/// its bounds and scale, and its distribution when it has one beyond uniform and loguniform.
fn range_values(
    t: &toml::Table,
    label: &str,
    key: &str,
    form: &str,
    mode: Mode,
    base: &Scene,
) -> Result<(AxisValues, Option<Marginal>), String> {
    if matches!(mode, Mode::Grid | Mode::Zip) {
        return Err(format!(
            "{label}: a `{form}` axis needs sampling mode lhs or sobol, or saltelli (mode is {}); use values, linspace or logspace",
            mode.name()
        ));
    }
    let range = parse_range(t, label)?;
    let log = log_scale(t, label)?;
    if let Some((low, _)) = range {
        if log && low <= 0.0 {
            return Err(format!(
                "{label}: `scale = \"log\"` (dist = \"loguniform\") needs low > 0, got {low}"
            ));
        }
    }
    let marginal = parse_dist(t, label, key, range, base)?;
    let (low, high) = match (range, marginal) {
        (Some(r), _) => r,
        (None, Some(m)) => m.distribution().support(),
        (None, None) => unreachable!("a range axis without a range has a distribution"),
    };
    Ok((AxisValues::Range { low, high, log }, marginal))
}

/// `range = [low, high]`, when the axis gives one: two finite numbers, low not above high.
fn parse_range(t: &toml::Table, label: &str) -> Result<Option<(f64, f64)>, String> {
    let Some(r) = t.get("range") else {
        return Ok(None);
    };
    let arr = r
        .as_array()
        .filter(|a| a.len() == 2)
        .ok_or_else(|| format!("{label}: `range` must be [low, high], got {r}"))?;
    let (low, high) = match (as_number(&arr[0]), as_number(&arr[1])) {
        (Some(a), Some(b)) if a.is_finite() && b.is_finite() => (a, b),
        _ => {
            return Err(format!(
                "{label}: `range` must be two finite numbers, got {r}"
            ))
        }
    };
    if low > high {
        return Err(format!("{label}: `range` low {low} is above high {high}"));
    }
    Ok(Some((low, high)))
}

/// Whether the range is drawn log-uniformly: `scale = "log"` or `dist = "loguniform"` (which
/// must not contradict each other); `scale` goes with no other distribution.
fn log_scale(t: &toml::Table, label: &str) -> Result<bool, String> {
    let dist_name = t.get("dist").and_then(Value::as_str);
    let log = match (t.get("scale"), dist_name) {
        (None, Some("loguniform")) => true,
        (None, _) => false,
        (Some(_), Some(d)) if d != "uniform" && d != "loguniform" => {
            return Err(format!(
                "{label}: `scale` and dist = \"{d}\" do not go together (dist = \"loguniform\" is scale = \"log\")"
            ))
        }
        (Some(Value::String(s)), d) if s == "linear" => {
            if d == Some("loguniform") {
                return Err(format!(
                    "{label}: scale = \"linear\" contradicts dist = \"loguniform\""
                ));
            }
            false
        }
        (Some(Value::String(s)), _) if s == "log" => true,
        (Some(other), _) => {
            return Err(format!(
                "{label}: `scale` = {other}: allowed \"linear\" or \"log\""
            ))
        }
    };
    Ok(log)
}

/// What the axis's values are: numbers, strings or booleans, all of one kind, the numbers
/// finite. A range is numbers.
fn axis_kind(values: &AxisValues, label: &str) -> Result<AxisKind, String> {
    let vals = match values {
        AxisValues::Range { .. } => return Ok(AxisKind::Number),
        AxisValues::List(vals) => vals,
    };
    let kind_of = |v: &Value| match v {
        Value::Float(_) | Value::Integer(_) => Some(AxisKind::Number),
        Value::String(_) => Some(AxisKind::Text),
        Value::Boolean(_) => Some(AxisKind::Bool),
        _ => None,
    };
    let first = kind_of(&vals[0]).ok_or_else(|| {
        format!(
            "{label}: values must be numbers, strings or booleans, got {}",
            type_name(&vals[0])
        )
    })?;
    for v in vals {
        if kind_of(v) != Some(first) {
            return Err(format!(
                "{label}: values must all be of one kind (numbers, strings or booleans), got {v}"
            ));
        }
        if let Some(f) = as_number(v) {
            if !f.is_finite() {
                return Err(format!("{label}: value {v} is not finite"));
            }
        }
    }
    Ok(first)
}
