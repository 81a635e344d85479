//! Scenes from Python: a path, a dict (sections as sub-dicts, or `"section.key"` names),
//! `None` for the defaults, or a [`PreparedScene`] read and checked once; overrides applied
//! after it; the key table.

use std::path::Path;

use cushion_model::{Module, Scene};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use crate::convert::{from_toml, to_table, to_toml};
use crate::errors::{config_error, read_file};

/// A scene read and checked once, to run many times: ``cushion.Scene(scene=None, set=None)``
/// takes what :func:`cushion.simulate` takes (a scene file, a dict of scene keys, or None for
/// the defaults; overrides ``{"section.key": value}`` after it) and raises
/// :class:`cushion.ConfigError` for bad input at once (:class:`FileNotFoundError`, or another
/// :class:`OSError`, for a scene file that cannot be read). Pass it to :func:`cushion.simulate` in
/// place of the file or dict: a run then starts from a copy of it.
//
// (Reading the paper's scene file and parsing its TOML costs about 18 µs, a fifth of its run
// at rtol 1e-6; a dict of every key, about 6 µs.)
#[pyclass(name = "Scene", module = "cushion._cushion", frozen)]
pub struct PreparedScene {
    pub scene: Scene,
}

#[pymethods]
impl PreparedScene {
    #[new]
    #[pyo3(signature = (scene=None, set=None))]
    fn new(scene: Option<&Bound<'_, PyAny>>, set: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut s = scene_from(scene)?;
        apply_set(&mut s, set)?;
        s.validate().map_err(config_error)?;
        Ok(PreparedScene { scene: s })
    }

    /// Every key and its value, ``{"section.key": value}`` (what :func:`cushion.load_scene`
    /// returns for a file).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        flat(py, &self.scene)
    }

    /// Pickled as its keys, so that a scene can go to another process (multiprocessing, a Dask
    /// worker) and be checked again there.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let d = flat(slf.py(), &slf.get().scene)?;
        Ok((slf.get_type().into_any(), (d,)))
    }

    fn __repr__(&self) -> String {
        let s = &self.scene;
        format!(
            "<cushion.Scene module='{}' t_end={} s dead_time={} s method='{}'>",
            s.module.name(),
            s.t_end,
            s.robot.dead_time,
            s.solver.method.name()
        )
    }
}

/// The scene a user gave: `None` (the defaults), a path to a scene file, a dict, or a
/// [`PreparedScene`].
pub fn scene_from(scene: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
    let Some(s) = scene else {
        return Ok(Scene::default());
    };
    if s.is_none() {
        return Ok(Scene::default());
    }
    if let Ok(p) = s.cast::<PreparedScene>() {
        return Ok(p.get().scene.clone());
    }
    if s.hasattr("__fspath__")? {
        let p = s.call_method0("__fspath__")?;
        return scene_from(Some(&p));
    }
    if let Ok(p) = s.cast::<PyString>() {
        let path = Path::new(p.to_str()?);
        read_file(path)?;
        return Scene::from_file(path).map_err(config_error);
    }
    if let Ok(d) = s.cast::<PyDict>() {
        let table = to_table("", d)?;
        let mut scene = Scene::default();
        scene.apply_table(&table).map_err(config_error)?;
        return Ok(scene);
    }
    Err(config_error(format!(
        "scene = {}: expected a path to a scene file (TOML), a dict of scene keys, a cushion.Scene, or None",
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

/// Every key as `(key, default, unit, description)`, in the order of docs/scene-keys.md (`Scene::keys()`).
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
    read_file(Path::new(path))?;
    let scene = Scene::from_file(Path::new(path)).map_err(config_error)?;
    flat(py, &scene)
}
