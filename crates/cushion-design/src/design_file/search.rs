//! `[search]` in a design file: the finest design cell, the worst-case tolerance, the
//! verification grid.

use toml::Value;

use super::{as_number, check_keys, SearchOptions};

pub(super) fn search(doc: &toml::Table) -> Result<SearchOptions, String> {
    let mut s = SearchOptions::default();
    let t = match doc.get("search") {
        None => return Ok(s),
        Some(Value::Table(t)) => t,
        Some(other) => return Err(format!("`search` must be a table [search], got {other}")),
    };
    check_keys(t, &["resolution", "tolerance", "verify"], "[search]")?;
    if let Some(v) = t.get("resolution") {
        s.resolution = match as_number(v) {
            Some(x) if x > 0.0 && x <= 1.0 => x,
            _ => {
                return Err(format!(
                    "[search] resolution = {v}: a fraction of each design range in (0, 1], e.g. 0.015625 (1/64)"
                ))
            }
        };
    }
    if let Some(v) = t.get("tolerance") {
        s.tolerance = match as_number(v) {
            Some(x) if x > 0.0 && x < 1.0 => x,
            _ => return Err(format!("[search] tolerance = {v}: a number in (0, 1)")),
        };
    }
    if let Some(v) = t.get("verify") {
        s.verify = match v {
            Value::Integer(n) if *n >= 2 && *n <= 10_000 => *n as usize,
            _ => {
                return Err(format!(
                    "[search] verify = {v}: an integer from 2 to 10000 (points per for_all range)"
                ))
            }
        };
    }
    Ok(s)
}
