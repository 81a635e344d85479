//! The `[[axis]]` list: each axis (`axis.rs`), then the checks across axes: distinct keys, none
//! also in `[set]`, one length under zip, the sobol dimension limit and a valid saltelli sample.

use std::collections::BTreeSet;

use cushion_model::Scene;
use cushion_sensitivity::{Marginal, SaltelliSample, SensitivityError};
use toml::Value;

use super::axis::parse_axis;
use super::sampling::Sampling;
use super::{list_len, Axis, Mode};

/// The axes in file order, and per axis its distribution when it has one.
pub(super) fn parse_axes(
    doc: &toml::Table,
    sampling: &Sampling,
    base: &Scene,
    set: &[(String, Value)],
) -> Result<(Vec<Axis>, Vec<Option<Marginal>>), String> {
    let mut axes = Vec::new();
    let mut marginals = Vec::new();
    match doc.get("axis") {
        None => {}
        Some(Value::Array(arr)) => {
            for (i, v) in arr.iter().enumerate() {
                let (axis, marginal) = parse_axis(i, v, sampling.mode, base)?;
                axes.push(axis);
                marginals.push(marginal);
            }
        }
        Some(_) => return Err("`axis` must be an array of tables [[axis]]".to_string()),
    }
    check_keys_once(&axes, set)?;
    if sampling.mode == Mode::Zip {
        check_zip_lengths(&axes)?;
    }
    if sampling.mode == Mode::Sobol && axes.len() as u32 > sobol_burley::NUM_DIMENSIONS {
        return Err(format!(
            "sobol takes at most {} axes",
            sobol_burley::NUM_DIMENSIONS
        ));
    }
    if sampling.mode == Mode::Saltelli {
        check_saltelli(&axes, sampling)?;
    }
    Ok((axes, marginals))
}

/// Every key is set once: by one axis, and not also in `[set]`.
fn check_keys_once(axes: &[Axis], set: &[(String, Value)]) -> Result<(), String> {
    let mut seen = BTreeSet::new();
    for (i, a) in axes.iter().enumerate() {
        if !seen.insert(a.key.clone()) {
            return Err(format!(
                "[[axis]] #{} (`{}`): the key has another axis already",
                i + 1,
                a.key
            ));
        }
        if set.iter().any(|(k, _)| k == &a.key) {
            return Err(format!(
                "[[axis]] #{} (`{}`): the key is also in [set]; keep one",
                i + 1,
                a.key
            ));
        }
    }
    Ok(())
}

/// zip takes the i-th value of every axis, so all axes have the first one's length.
fn check_zip_lengths(axes: &[Axis]) -> Result<(), String> {
    let Some(first) = axes.first() else {
        return Ok(());
    };
    let n0 = list_len(first);
    for (i, a) in axes.iter().enumerate() {
        if list_len(a) != n0 {
            return Err(format!(
                "[[axis]] #{} (`{}`): zip needs axes of one length: it has {} values, `{}` has {}",
                i + 1,
                a.key,
                list_len(a),
                first.key,
                n0
            ));
        }
    }
    Ok(())
}

/// The saltelli sample can be built from these axes and `[sampling]`.
fn check_saltelli(axes: &[Axis], sampling: &Sampling) -> Result<(), String> {
    SaltelliSample::new(
        axes.len(),
        sampling.samples as usize,
        sampling.second_order,
        sampling.seed,
    )
    .map_err(|e| match e {
        SensitivityError::Config {
            key,
            value,
            allowed,
        } if key == "inputs" => {
            format!(
                "[[axis]]: saltelli needs 1 to {} `range` axes, got {value} ({allowed})",
                SaltelliSample::MAX_INPUTS
            )
        }
        other => format!("[sampling] {other}"),
    })?;
    Ok(())
}
