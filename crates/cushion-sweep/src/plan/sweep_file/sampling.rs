//! The `[sampling]` table: `mode`, `samples`, `seed` and `second_order`, each checked against
//! the mode.

use cushion_sensitivity::SaltelliSample;
use toml::Value;

use super::toml_helpers::check_keys;
use super::{Mode, MAX_RUNS, SOBOL_MAX_SAMPLES};

/// A checked `[sampling]` table.
pub(super) struct Sampling {
    pub mode: Mode,
    /// 0 for grid and zip, whose axes set the number of runs.
    pub samples: u64,
    pub seed: u64,
    pub second_order: bool,
}

pub(super) fn parse_sampling(doc: &toml::Table) -> Result<Sampling, String> {
    let empty = toml::Table::new();
    let sampling = match doc.get("sampling") {
        None => &empty,
        Some(Value::Table(t)) => t,
        Some(_) => return Err("`sampling` must be a table [sampling]".to_string()),
    };
    check_keys(
        sampling,
        &["mode", "samples", "seed", "second_order"],
        "[sampling]",
    )?;
    let mode = parse_mode(sampling)?;
    let samples = parse_samples(sampling, mode)?;
    let seed = parse_seed(sampling, mode)?;
    if mode == Mode::Saltelli && !samples.is_power_of_two() {
        return Err(format!(
            "[sampling] samples = {samples}: saltelli takes a power of two (base points) from 1 to {}",
            SaltelliSample::MAX_BASE_POINTS
        ));
    }
    let second_order = parse_second_order(sampling, mode)?;
    Ok(Sampling {
        mode,
        samples,
        seed,
        second_order,
    })
}

/// Whether the mode draws `samples` points from a seed (rather than listing the axes' values).
fn draws_points(mode: Mode) -> bool {
    matches!(mode, Mode::Lhs | Mode::Sobol | Mode::Saltelli)
}

fn parse_mode(sampling: &toml::Table) -> Result<Mode, String> {
    match sampling.get("mode") {
        None => Ok(Mode::Grid),
        Some(Value::String(s)) => match s.as_str() {
            "grid" => Ok(Mode::Grid),
            "zip" => Ok(Mode::Zip),
            "lhs" => Ok(Mode::Lhs),
            "sobol" => Ok(Mode::Sobol),
            "saltelli" => Ok(Mode::Saltelli),
            _ => Err(format!(
                "[sampling] mode = {s:?}: allowed \"grid\", \"zip\", \"lhs\", \"sobol\", \"saltelli\""
            )),
        },
        Some(other) => Err(format!(
            "[sampling] mode = {other}: allowed \"grid\", \"zip\", \"lhs\", \"sobol\", \"saltelli\""
        )),
    }
}

fn parse_samples(sampling: &toml::Table, mode: Mode) -> Result<u64, String> {
    let samples = match (sampling.get("samples"), draws_points(mode)) {
        (None, true) => {
            return Err(format!(
                "[sampling] mode {} needs `samples` (an integer >= 1)",
                mode.name()
            ))
        }
        (None, false) => 0,
        (Some(_), false) => {
            return Err(format!(
                "[sampling] `samples` is for lhs, sobol and saltelli only (mode is {}: the axes set the number of runs)",
                mode.name()
            ))
        }
        (Some(Value::Integer(n)), true) if *n >= 1 => *n as u64,
        (Some(other), true) => {
            return Err(format!(
                "[sampling] samples = {other}: must be an integer >= 1"
            ))
        }
    };
    if mode == Mode::Sobol && samples > SOBOL_MAX_SAMPLES {
        return Err(format!(
            "[sampling] samples = {samples}: sobol gives at most {SOBOL_MAX_SAMPLES} points; use lhs for more"
        ));
    }
    if samples > MAX_RUNS {
        return Err(format!(
            "[sampling] samples = {samples}: at most {MAX_RUNS}"
        ));
    }
    Ok(samples)
}

fn parse_seed(sampling: &toml::Table, mode: Mode) -> Result<u64, String> {
    match (sampling.get("seed"), draws_points(mode)) {
        (None, _) => Ok(0),
        (Some(_), false) => Err(format!(
            "[sampling] `seed` is for lhs, sobol and saltelli only (mode is {})",
            mode.name()
        )),
        (Some(Value::Integer(n)), true) if *n >= 0 && (*n as u64) <= u32::MAX as u64 => {
            Ok(*n as u64)
        }
        (Some(other), true) => Err(format!(
            "[sampling] seed = {other}: must be an integer from 0 to {}",
            u32::MAX
        )),
    }
}

fn parse_second_order(sampling: &toml::Table, mode: Mode) -> Result<bool, String> {
    match (sampling.get("second_order"), mode) {
        (None, _) => Ok(true),
        (Some(Value::Boolean(b)), Mode::Saltelli) => Ok(*b),
        (Some(Value::Boolean(_)), _) => Err(format!(
            "[sampling] `second_order` is for saltelli only (mode is {})",
            mode.name()
        )),
        (Some(other), _) => Err(format!(
            "[sampling] second_order = {other}: must be true or false"
        )),
    }
}
