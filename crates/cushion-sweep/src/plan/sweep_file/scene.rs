//! The base `scene` (a path relative to the sweep file, or a table of scene keys) and the
//! `[set]` overrides applied to it.

use std::path::Path;

use cushion_model::Scene;
use toml::Value;

/// The base scene with `[set]` applied, and the `[set]` overrides in file order.
pub(super) fn parse_scene_and_set(
    doc: &toml::Table,
    path: &Path,
) -> Result<(Scene, Vec<(String, Value)>), String> {
    let mut base = parse_scene(doc, path)?;
    let mut set = Vec::new();
    if let Some(v) = doc.get("set") {
        let t = v.as_table().ok_or("`set` must be a table [set]")?;
        flatten("", t, &mut set);
    }
    for (k, v) in &set {
        base.set(k, v).map_err(|e| format!("[set] {e}"))?;
    }
    Ok((base, set))
}

/// `scene`: the default scene, a scene file (relative to the sweep file's folder) or a table.
fn parse_scene(doc: &toml::Table, path: &Path) -> Result<Scene, String> {
    match doc.get("scene") {
        None => Ok(Scene::default()),
        Some(Value::String(s)) => {
            let dir = path.parent().unwrap_or(Path::new(""));
            let scene_path = dir.join(s);
            Scene::from_file(&scene_path).map_err(|e| format!("`scene` = {s:?}: {e}"))
        }
        Some(Value::Table(t)) => {
            let mut scene = Scene::default();
            scene.apply_table(t).map_err(|e| format!("`scene`: {e}"))?;
            Ok(scene)
        }
        Some(other) => Err(format!(
            "`scene` must be a path string or a table of scene keys, got {other}"
        )),
    }
}

/// Flatten `{solver = {rtol = 1e-6}}` (unquoted dotted keys) into `solver.rtol`.
fn flatten(prefix: &str, t: &toml::Table, out: &mut Vec<(String, Value)>) {
    for (k, v) in t {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            Value::Table(inner) => flatten(&key, inner, out),
            _ => out.push((key, v.clone())),
        }
    }
}
