//! Scenes from Python: a path, a dict (sections as sub-dicts, or `"section.key"` names), or
//! `None` for the defaults; overrides applied after it; the key table.

use std::path::Path;

use cushion_model::{Module, Scene};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use crate::convert::{from_toml, to_table, to_toml};
use crate::errors::config_error;

/// The scene a user gave: `None` (the defaults), a path to a scene file, or a dict.
pub fn scene_from(scene: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
    let Some(s) = scene else {
        return Ok(Scene::default());
    };
    if s.is_none() {
        return Ok(Scene::default());
    }
    if let Ok(p) = s.cast::<PyString>() {
        return Scene::from_file(Path::new(p.to_str()?)).map_err(config_error);
    }
    if let Ok(d) = s.cast::<PyDict>() {
        let table = to_table("", d)?;
        let mut scene = Scene::default();
        scene.apply_table(&table).map_err(config_error)?;
        return Ok(scene);
    }
    Err(config_error(format!(
        "scene = {}: expected a path to a scene file (TOML), a dict of scene keys, or None",
        s.repr()?
    )))
}

/// Apply `{"section.key": value}` overrides in order.
pub fn apply_set(scene: &mut Scene, set: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    if let Some(set) = set {
        for (k, v) in set.iter() {
            let key: String = k.extract().map_err(|_| {
                config_error(format!(
                    "set: keys are \"section.key\" strings, got {}",
                    k.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
            let value = to_toml(&key, &v)?;
            scene.set(&key, &value).map_err(config_error)?;
        }
    }
    Ok(())
}

/// Every key and its value, `{"section.key": value}`, in the order of `cushion.keys()`.
fn flat<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for key in Scene::keys() {
        let v = scene.get(key).map_err(config_error)?;
        d.set_item(*key, from_toml(py, &v)?)?;
    }
    Ok(d)
}

/// The default scene of a module as `{"section.key": value}`.
#[pyfunction]
#[pyo3(signature = (module = "hydraulic"))]
pub fn defaults<'py>(py: Python<'py>, module: &str) -> PyResult<Bound<'py, PyDict>> {
    let m = Module::from_name(module).ok_or_else(|| {
        config_error(format!(
            "module = {module:?}: expected \"hydraulic\", \"bistable\" or \"rigid\""
        ))
    })?;
    let mut scene = Scene::default();
    scene
        .set("module", &toml::Value::String(m.name().into()))
        .map_err(config_error)?;
    flat(py, &scene)
}

/// Every key as `(key, default, unit, description)`, in SPEC order.
#[pyfunction]
pub fn keys<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let scene = Scene::default();
    let out = PyList::empty(py);
    for info in Scene::key_info() {
        let v = scene.get(info.key).map_err(config_error)?;
        out.append(PyTuple::new(
            py,
            [
                PyString::new(py, info.key).into_any(),
                from_toml(py, &v)?,
                PyString::new(py, info.unit).into_any(),
                PyString::new(py, info.description).into_any(),
            ],
        )?)?;
    }
    Ok(out)
}

/// A scene file read and parsed (not validated) as `{"section.key": value}`, every key.
#[pyfunction]
pub fn load_scene<'py>(py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let scene = Scene::from_file(Path::new(path)).map_err(config_error)?;
    flat(py, &scene)
}
