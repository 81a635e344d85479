//! One `[[axis]]` of a sweep file: its key and its values (`values`, `linspace`, `logspace`,
//! `range` with `scale`), checked against the sampling mode.

use super::*;

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

pub(super) fn parse_axis(i: usize, v: &Value, mode: Mode) -> Result<Axis, String> {
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
    let label = format!("[[axis]] #{} (`{key}`)", i + 1);
    check_keys(
        t,
        &["key", "values", "linspace", "logspace", "range", "scale"],
        &label,
    )?;
    if !Scene::keys().contains(&key.as_str()) {
        return Err(format!(
            "{label}: unknown scene key `{key}` (allowed: {})",
            Scene::keys().join(", ")
        ));
    }
    let forms: Vec<&str> = ["values", "linspace", "logspace", "range"]
        .into_iter()
        .filter(|f| t.contains_key(*f))
        .collect();
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
            let (a, b, n) = spaced(&label, "linspace", &t["linspace"])?;
            AxisValues::List(linspace(a, b, n).into_iter().map(Value::Float).collect())
        }
        "logspace" => {
            let (a, b, n) = spaced(&label, "logspace", &t["logspace"])?;
            if a <= 0.0 || b <= 0.0 {
                return Err(format!(
                    "{label}: `logspace` takes endpoints (not exponents), both > 0, got [{a}, {b}, {n}]"
                ));
            }
            AxisValues::List(logspace(a, b, n).into_iter().map(Value::Float).collect())
        }
        _ => {
            if matches!(mode, Mode::Grid | Mode::Zip) {
                return Err(format!(
                    "{label}: a `range` axis needs sampling mode lhs or sobol (mode is {}); use values, linspace or logspace",
                    mode.name()
                ));
            }
            let r = &t["range"];
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
            let log = match t.get("scale") {
                None => false,
                Some(Value::String(s)) if s == "linear" => false,
                Some(Value::String(s)) if s == "log" => true,
                Some(other) => {
                    return Err(format!(
                        "{label}: `scale` = {other}: allowed \"linear\" or \"log\""
                    ))
                }
            };
            if log && low <= 0.0 {
                return Err(format!(
                    "{label}: `scale = \"log\"` needs low > 0, got {low}"
                ));
            }
            AxisValues::Range { low, high, log }
        }
    };
    let kind = match &values {
        AxisValues::Range { .. } => AxisKind::Number,
        AxisValues::List(vals) => {
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
            first
        }
    };
    Ok(Axis { key, values, kind })
}
