//! Scene values from TOML and back: numbers, switches, counts and named choices, each checked
//! and named in its error.

use super::*;

/// A value type a key can hold: conversion from and to TOML, and its name in messages.
pub(super) trait KeyValue: Sized {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError>;
    fn to_value(&self) -> toml::Value;
}

fn show(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        toml::Value::Float(f) => format_float(*f),
        other => other.to_string(),
    }
}

pub(super) fn format_float(f: f64) -> String {
    if f.is_nan() {
        "nan".into()
    } else if f.is_infinite() {
        if f > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else if f != 0.0 && (f.abs() < 1e-4 || f.abs() >= 1e16) {
        // `1e-300`, not three hundred zeros
        format!("{f:e}")
    } else {
        format!("{f}")
    }
}

fn wrong_type(key: &str, v: &toml::Value, expected: &str) -> ConfigError {
    ConfigError::WrongType {
        key: key.into(),
        value: show(v),
        expected: expected.into(),
    }
}

impl KeyValue for f64 {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        match v {
            toml::Value::Float(f) => Ok(*f),
            toml::Value::Integer(i) => Ok(*i as f64),
            _ => Err(wrong_type(key, v, "a number")),
        }
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::Float(*self)
    }
}

impl KeyValue for bool {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        match v {
            toml::Value::Boolean(b) => Ok(*b),
            _ => Err(wrong_type(key, v, "true or false")),
        }
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::Boolean(*self)
    }
}

impl KeyValue for u64 {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        match v {
            toml::Value::Integer(i) if *i >= 0 => Ok(*i as u64),
            toml::Value::Integer(_) => Err(ConfigError::InvalidValue {
                key: key.into(),
                value: show(v),
                allowed: "must be a non-negative integer".into(),
            }),
            toml::Value::Float(f) if f.fract() == 0.0 && *f >= 0.0 && *f < 9.0e18 => Ok(*f as u64),
            _ => Err(wrong_type(key, v, "a non-negative integer")),
        }
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::Integer((*self).min(i64::MAX as u64) as i64)
    }
}

fn choice<T>(
    key: &str,
    v: &toml::Value,
    names: &[&str],
    parse: impl Fn(&str) -> Option<T>,
) -> Result<T, ConfigError> {
    let expected = format!(
        "one of {}",
        names
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    );
    match v {
        toml::Value::String(s) => parse(s).ok_or_else(|| ConfigError::InvalidValue {
            key: key.into(),
            value: show(v),
            allowed: format!("must be {expected}"),
        }),
        _ => Err(wrong_type(key, v, &format!("a string, {expected}"))),
    }
}

impl KeyValue for Module {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        choice(
            key,
            v,
            &["hydraulic", "bistable", "rigid"],
            Module::from_name,
        )
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::String(self.name().into())
    }
}

impl KeyValue for RobotStart {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        choice(key, v, &["cruising", "rest"], |s| match s {
            "cruising" => Some(RobotStart::Cruising),
            "rest" => Some(RobotStart::Rest),
            _ => None,
        })
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::String(self.name().into())
    }
}

impl KeyValue for Method {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        choice(key, v, &Method::NAMES, Method::from_name)
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::String(self.name().into())
    }
}

/// The name of a stiffness setting (`warn`, `stop`, `off`).
pub fn stiffness_name(a: StiffnessAction) -> &'static str {
    match a {
        StiffnessAction::Off => "off",
        StiffnessAction::Warn => "warn",
        StiffnessAction::Stop => "stop",
    }
}

impl KeyValue for StiffnessAction {
    fn from_value(key: &str, v: &toml::Value) -> Result<Self, ConfigError> {
        choice(key, v, &["warn", "stop", "off"], |s| match s {
            "warn" => Some(StiffnessAction::Warn),
            "stop" => Some(StiffnessAction::Stop),
            "off" => Some(StiffnessAction::Off),
            _ => None,
        })
    }
    fn to_value(&self) -> toml::Value {
        toml::Value::String(stiffness_name(*self).into())
    }
}
