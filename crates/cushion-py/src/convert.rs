//! Python values <-> the TOML values of scene and sweep keys.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::errors::config_error;

/// A Python value as a TOML value; `key` names it in the error. Booleans, integers, floats
/// (numpy scalars too), strings, lists and tuples, dicts (string keys).
pub fn to_toml(key: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return match v.extract::<i64>() {
            Ok(i) => Ok(toml::Value::Integer(i)),
            Err(_) => Ok(toml::Value::Float(v.extract::<f64>()?)),
        };
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(toml::Value::Table(to_table(key, d)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in v.try_iter()?.enumerate() {
            out.push(to_toml(&format!("{key}[{i}]"), &item?)?);
        }
        return Ok(toml::Value::Array(out));
    }
    // numpy integers and floats, and anything else that says what number it is
    if v.hasattr("__index__")? {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if v.hasattr("__float__")? {
        if let Ok(f) = v.call_method0("__float__").and_then(|f| f.extract::<f64>()) {
            return Ok(toml::Value::Float(f));
        }
    }
    Err(config_error(format!(
        "`{key}` = {}: wrong type {}, expected a number, string, boolean, list or dict",
        v.repr()
            .map(|r| r.to_string())
            .unwrap_or_else(|_| "?".into()),
        v.get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into()),
    )))
}

/// A dict with string keys as a TOML table.
pub fn to_table(key: &str, d: &Bound<'_, PyDict>) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let name: String = k.extract().map_err(|_| {
            config_error(format!(
                "`{key}`: keys must be strings, got {}",
                k.repr().map(|r| r.to_string()).unwrap_or_default()
            ))
        })?;
        let path = if key.is_empty() {
            name.clone()
        } else {
            format!("{key}.{name}")
        };
        t.insert(name, to_toml(&path, &v)?);
    }
    Ok(t)
}

/// A TOML value as a Python value.
pub fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(from_toml(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, from_toml(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// A file config the user gave (a sweep, a design question): a path to its TOML file, or a
/// dict of the same shape, parsed by the library's own `from_file` / `from_str_at`. A file that
/// cannot be read is Python's `OSError` subclass; anything the parser refuses a `ConfigError`.
/// A dict without `name` is named `default_name`; a relative `scene` in it is taken from the
/// working folder. `what` names the kind in messages ("sweep", "design").
pub fn file_config<T>(
    config: &Bound<'_, PyAny>,
    what: &str,
    default_name: &str,
    from_file: fn(&std::path::Path) -> Result<T, String>,
    from_str_at: fn(&str, &std::path::Path) -> Result<T, String>,
) -> PyResult<T> {
    use pyo3::types::PyString;
    use std::path::Path;
    if let Ok(p) = config.cast::<PyString>() {
        let path = Path::new(p.to_str()?);
        crate::errors::read_file(path)?;
        return from_file(path).map_err(config_error);
    }
    if let Ok(d) = config.cast::<PyDict>() {
        let mut table = to_table("", d)?;
        table
            .entry("name")
            .or_insert_with(|| toml::Value::String(default_name.into()));
        let text = toml::to_string(&table)
            .map_err(|e| config_error(format!("{what} config: cannot be written as TOML: {e}")))?;
        return from_str_at(&text, Path::new("<dict>"))
            .map_err(|e| config_error(format!("{what} config: {e}")));
    }
    Err(config_error(format!(
        "config = {}: expected a path to a {what} file (TOML) or a dict of the same shape",
        config.repr()?
    )))
}
