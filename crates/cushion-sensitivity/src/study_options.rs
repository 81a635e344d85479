//! The `[sensitivity]` table of a sweep file: which outputs, the bootstrap, and what to do with
//! runs that did not end `ok`.

use crate::error::{config, SensitivityError};

/// What to do with runs that did not end `ok`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnFailed {
    /// Stop, naming how many runs failed and for which inputs (default).
    Stop,
    /// Drop the whole block of each base point that holds a failed run, and say how many.
    DropBasePoint,
}

/// The `[sensitivity]` table of a sweep file.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyOptions {
    /// The outputs to analyse (default: every numeric summary column).
    pub outputs: Option<Vec<String>>,
    pub resamples: usize,
    pub conf_level: f64,
    /// Seeds the bootstrap.
    pub seed: u64,
    pub on_failed: OnFailed,
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions {
            outputs: None,
            resamples: 1000,
            conf_level: 0.95,
            seed: 0,
            on_failed: OnFailed::Stop,
        }
    }
}

/// The keys of `[sensitivity]`.
pub const STUDY_KEYS: &[&str] = &["outputs", "resamples", "conf_level", "seed", "on_failed"];

impl StudyOptions {
    /// Read a `[sensitivity]` table (absent: the defaults). Errors name the key, the value and
    /// what is allowed.
    pub fn from_table(table: Option<&toml::Table>) -> Result<StudyOptions, SensitivityError> {
        let mut o = StudyOptions::default();
        let Some(t) = table else {
            return Ok(o);
        };
        for (k, v) in t {
            if !STUDY_KEYS.contains(&k.as_str()) {
                return Err(config(
                    format!("[sensitivity] {k}"),
                    v,
                    format!("unknown key (allowed: {})", STUDY_KEYS.join(", ")),
                ));
            }
        }
        if let Some(v) = t.get("outputs") {
            let list = v
                .as_array()
                .and_then(|a| {
                    a.iter()
                        .map(|x| x.as_str().map(str::to_string))
                        .collect::<Option<Vec<String>>>()
                })
                .filter(|a| !a.is_empty())
                .ok_or_else(|| {
                    config(
                        "[sensitivity] outputs",
                        v,
                        "must be a non-empty list of summary field names",
                    )
                })?;
            o.outputs = Some(list);
        }
        if let Some(v) = t.get("resamples") {
            o.resamples = match v.as_integer() {
                Some(n) if (2..=1_000_000).contains(&n) => n as usize,
                _ => {
                    return Err(config(
                        "[sensitivity] resamples",
                        v,
                        "must be an integer from 2 to 1000000",
                    ))
                }
            };
        }
        if let Some(v) = t.get("conf_level") {
            o.conf_level = match v.as_float() {
                Some(x) if x > 0.0 && x < 1.0 => x,
                _ => {
                    return Err(config(
                        "[sensitivity] conf_level",
                        v,
                        "must be a number strictly between 0 and 1 (e.g. 0.95)",
                    ))
                }
            };
        }
        if let Some(v) = t.get("seed") {
            o.seed = match v.as_integer() {
                Some(n) if n >= 0 => n as u64,
                _ => return Err(config("[sensitivity] seed", v, "must be an integer >= 0")),
            };
        }
        if let Some(v) = t.get("on_failed") {
            o.on_failed = match v.as_str() {
                Some("stop") => OnFailed::Stop,
                Some("drop_base_point") => OnFailed::DropBasePoint,
                _ => {
                    return Err(config(
                        "[sensitivity] on_failed",
                        v,
                        "allowed \"stop\" or \"drop_base_point\"",
                    ))
                }
            };
        }
        Ok(o)
    }
}
