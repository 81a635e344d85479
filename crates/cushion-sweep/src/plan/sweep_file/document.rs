//! The sweep file as a TOML document: its syntax, its top-level keys, its `name`, and the
//! `[sensitivity]` table (kept as written for `cushion sensitivity`).

use std::path::Path;

use toml::Value;

use super::toml_helpers::check_keys;

/// Parse the TOML text and check its top-level keys. A syntax error names its line and column.
pub(super) fn parse_document(text: &str) -> Result<toml::Table, String> {
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        // One line: "line L, column C: what".
        let msg = e.message().trim().replace('\n', "; ");
        match e.span() {
            Some(span) => {
                let before = &text[..span.start.min(text.len())];
                let line = before.matches('\n').count() + 1;
                let col = before.len() - before.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
                format!("TOML syntax error at line {line}, column {col}: {msg}")
            }
            None => format!("TOML syntax error: {msg}"),
        }
    })?;
    check_keys(
        &doc,
        &[
            "name",
            "scene",
            "set",
            "sampling",
            "axis",
            "output",
            "sensitivity",
        ],
        "the sweep file",
    )?;
    Ok(doc)
}

/// `name`, by default the file's stem; it must be a plain folder name.
pub(super) fn parse_name(doc: &toml::Table, path: &Path) -> Result<String, String> {
    let name = match doc.get("name") {
        None => path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep".to_string()),
        Some(Value::String(s)) => s.clone(),
        Some(other) => return Err(format!("`name` must be a string, got {other}")),
    };
    if name.is_empty()
        || name == "."
        || name == ".."
        || name.contains(['/', '\\'])
        || name.chars().any(|c| c.is_control())
    {
        return Err(format!(
            "`name` = {name:?}: must be a plain folder name (no slashes), it names runs/<name>"
        ));
    }
    Ok(name)
}

/// The `[sensitivity]` table, unchecked here: `cushion sensitivity` reads it.
pub(super) fn parse_sensitivity(doc: &toml::Table) -> Result<Option<toml::Table>, String> {
    match doc.get("sensitivity") {
        None => Ok(None),
        Some(Value::Table(t)) => Ok(Some(t.clone())),
        Some(_) => Err("`sensitivity` must be a table [sensitivity]".to_string()),
    }
}
