//! Small readers of TOML values shared by the sweep file's phases and the design file's: unknown
//! keys, numbers and type names.

use toml::Value;

pub(super) fn type_name(v: &Value) -> &'static str {
    v.type_str()
}

/// A TOML integer or float as a number.
pub fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// Every key of `table` is in `allowed`; else the message names the key, where it is and what
/// is allowed.
pub fn check_keys(table: &toml::Table, allowed: &[&str], where_: &str) -> Result<(), String> {
    for k in table.keys() {
        if !allowed.contains(&k.as_str()) {
            return Err(format!(
                "unknown key `{k}` in {where_} (allowed: {})",
                allowed.join(", ")
            ));
        }
    }
    Ok(())
}
