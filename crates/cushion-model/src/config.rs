//! Scene files: the keys of SPEC section 7, their defaults, units and checks.
//!
//! A scene file is TOML. Top-level keys are `module` and `t_end`; every other key lives in a
//! section (`[robot]`, `[tool]`, `[object]`, `[stops]`, `[hydraulic]`, `[bistable]`,
//! `[solver]`, `[energy]`) and is addressed as `section.name` everywhere (`--set`, sweep axes,
//! Python keyword overrides). All values are SI; no unit is ever part of a key.
//!
//! Extensions beyond SPEC section 7 (all optional, with defaults that reproduce the SPEC):
//! `object.enabled`, `energy.ledger`, `solver.max_steps`, `solver.fixed_step`,
//! `solver.stiffness`, `solver.early_end`, `solver.ringing_tail`, `hydraulic.cavitation`,
//! `hydraulic.cavitation_pressure`, `hydraulic.bulk_modulus`, `hydraulic.chamber_volume`.
//!
//! Every key's unit and description live in one list, the `scene_keys!` invocation below;
//! [`Scene::key_info`] returns it, and `docs/scene-keys.md` is its table with the defaults (a
//! test keeps that page current).
//!
//! Parsing never validates combinations; [`Scene::validate`] does (and `simulate` calls it).
//! Every error names the key, the value and what is allowed.

mod validate;

use cushion_ode::{Method, StiffnessAction};
use thiserror::Error;

/// Which compliance module sits between flange and tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Module {
    Hydraulic,
    Bistable,
    Rigid,
}

impl Module {
    /// The name users type.
    pub fn name(self) -> &'static str {
        match self {
            Module::Hydraulic => "hydraulic",
            Module::Bistable => "bistable",
            Module::Rigid => "rigid",
        }
    }
    /// Parse a user's name.
    pub fn from_name(s: &str) -> Option<Module> {
        match s {
            "hydraulic" => Some(Module::Hydraulic),
            "bistable" => Some(Module::Bistable),
            "rigid" => Some(Module::Rigid),
            _ => None,
        }
    }
}

/// How the robot starts (`robot.start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotStart {
    /// Already moving at `robot.approach_speed` at `t = 0`.
    Cruising,
    /// At rest at `t = 0`, accelerating at `robot.acceleration` up to the approach speed.
    Rest,
}

impl RobotStart {
    pub fn name(self) -> &'static str {
        match self {
            RobotStart::Cruising => "cruising",
            RobotStart::Rest => "rest",
        }
    }
}

/// A bad scene, key or value. Every message names the key, the value and what is allowed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ConfigError {
    #[error("unknown key `{key}` (allowed: {allowed})")]
    UnknownKey { key: String, allowed: String },
    #[error("`{key}` = {value}: wrong type, expected {expected}")]
    WrongType {
        key: String,
        value: String,
        expected: String,
    },
    #[error("`{key}` = {value}: {allowed}")]
    InvalidValue {
        key: String,
        value: String,
        allowed: String,
    },
    #[error("{path}: {message}")]
    File { path: String, message: String },
}

impl ConfigError {
    /// The key the error is about, when it is about one.
    pub fn key(&self) -> Option<&str> {
        match self {
            ConfigError::UnknownKey { key, .. }
            | ConfigError::WrongType { key, .. }
            | ConfigError::InvalidValue { key, .. } => Some(key),
            ConfigError::File { .. } => None,
        }
    }
}

/// `[robot]`: the prescribed flange motion (SPEC section 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// `robot.approach_speed`: `v_max`, flange speed before the impact, m/s (> 0).
    pub approach_speed: f64,
    /// `robot.brake_deceleration`: `a_brake`, deceleration once braking, m/s^2 (> 0).
    pub brake_deceleration: f64,
    /// `robot.dead_time`: `DT`, delay from detection to the start of braking, s (>= 0).
    pub dead_time: f64,
    /// `robot.start`: `"cruising"` (moving at `v_max` at t = 0) or `"rest"`.
    pub start: RobotStart,
    /// `robot.acceleration`: `a_acc`, acceleration from rest (start = rest only), m/s^2 (> 0).
    pub acceleration: f64,
}

/// `[tool]`: the end-effector.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// `tool.mass`: `m_t`, kg (> 0).
    pub mass: f64,
    /// `tool.sensor_threshold`: `s_sensor`, stroke at which the impact sensor switches, m,
    /// inside `(0, stops.stroke)`.
    pub sensor_threshold: f64,
    /// `tool.viscous_friction`: `b`, N s/m (>= 0).
    pub viscous_friction: f64,
    /// `tool.dry_friction`: `d`, Coulomb friction force, N (>= 0; > 0 adds stick-slip events).
    pub dry_friction: f64,
}

/// `[object]`: the small object on the plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// `object.enabled`: `false` removes the object (free tool, no contact). Extension.
    pub enabled: bool,
    /// `object.mass`: `m_p`, kg (> 0).
    pub mass: f64,
    /// `object.gap`: initial distance from the tool's face to the object's face, m (> 0).
    pub gap: f64,
    /// `object.contact_stiffness`: `k_c`, Hunt–Crossley stiffness, N/m^1.5 (> 0).
    pub contact_stiffness: f64,
    /// `object.contact_damping`: `chi_c`, Hunt–Crossley damping, N s/m^2.5 (>= 0).
    pub contact_damping: f64,
    /// `object.plane_friction`: `mu_plane`, Coulomb coefficient with the plane (0 = off), -.
    pub plane_friction: f64,
}

/// `[stops]`: the two end-stops of the module.
#[derive(Clone, Debug, PartialEq)]
pub struct Stops {
    /// `stops.stroke`: `L`, distance between forward and back stop, m (> 0).
    pub stroke: f64,
    /// `stops.stiffness`: `k_e`, Hunt–Crossley stiffness of both stops, N/m^1.5 (> 0).
    pub stiffness: f64,
    /// `stops.damping`: `chi_e`, Hunt–Crossley damping of both stops, N s/m^2.5 (>= 0).
    pub damping: f64,
}

/// `[hydraulic]`: the hydraulic module (SPEC section 2).
#[derive(Clone, Debug, PartialEq)]
pub struct Hydraulic {
    /// `hydraulic.piston_radius`: `R_p`, main cylinder radius, m (> 0).
    pub piston_radius: f64,
    /// `hydraulic.orifice_radius`: `R_o`, m (> 0, < `R_p`).
    pub orifice_radius: f64,
    /// `hydraulic.loss_coefficient`: `c0`, orifice loss coefficient, - (> 0).
    pub loss_coefficient: f64,
    /// `hydraulic.liquid_density`: `rho_L`, kg/m^3 (> 0).
    pub liquid_density: f64,
    /// `hydraulic.gas_pressure`: `p10`, gas pressure at `s = 0`, Pa (> 0).
    pub gas_pressure: f64,
    /// `hydraulic.gas_volume`: `V_g0`, gas volume at `s = 0`, m^3 (> `A_p * L`).
    pub gas_volume: f64,
    /// `hydraulic.gas_exponent`: `kappa`, adiabatic exponent, - (in (1, 2]).
    pub gas_exponent: f64,
    /// `hydraulic.cavitation`: bound the main chamber's pressure from below,
    /// `p_m >= hydraulic.cavitation_pressure` (events at its onset and end). Extension.
    pub cavitation: bool,
    /// `hydraulic.cavitation_pressure`: `p_cav`, Pa (in the frame of `p10`; < `gas_pressure`).
    pub cavitation_pressure: f64,
    /// `hydraulic.bulk_modulus`: `beta`, liquid bulk modulus, Pa (>= 0). 0: the lumped,
    /// incompressible model of SPEC section 2; > 0: the richer model of SPEC section 6, with the
    /// main chamber pressure `p_m` and the volume moved through the orifice as states (stiff;
    /// about 1.5e9 for oil). Extension.
    pub bulk_modulus: f64,
    /// `hydraulic.chamber_volume`: liquid volume of the main chamber at `s = 0`, m^3
    /// (> `A_p * L`); used only with `bulk_modulus > 0`. Extension.
    pub chamber_volume: f64,
}

/// `[bistable]`: the von Mises snap-through element (SPEC section 4).
#[derive(Clone, Debug, PartialEq)]
pub struct Bistable {
    /// `bistable.spring_stiffness`: `k_b`, stiffness of each of the two springs, N/m (> 0).
    pub spring_stiffness: f64,
    /// `bistable.half_span`: `w`, m (> 0).
    pub half_span: f64,
    /// `bistable.apex_rise`: `h`, m (> 0).
    pub apex_rise: f64,
    /// `bistable.offset`: `e`, preload offset from the first stable point, m (in [0, h)).
    pub offset: f64,
}

/// `[solver]`: integrator settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Solver {
    /// `solver.method`: `"dp5"` (adaptive), `"rk4"` or `"euler"` (fixed step).
    pub method: Method,
    /// `solver.rtol`: relative tolerance, - (in (10 eps, 1), eps = 2.2e-16).
    pub rtol: f64,
    /// `solver.atol`: absolute tolerance, in each state's unit (> 0).
    pub atol: f64,
    /// `solver.max_steps`: most steps before giving up (>= 1). Extension.
    pub max_steps: u64,
    /// `solver.fixed_step`: step of `rk4` and `euler`, s (> 0). Extension.
    pub fixed_step: f64,
    /// `solver.stiffness`: `"warn"`, `"stop"` or `"off"`. Extension.
    pub stiffness: StiffnessAction,
    /// `solver.early_end`: end the run once nothing can change any more. Extension.
    pub early_end: bool,
    /// `solver.ringing_tail`: with `early_end`, end the run once only the tool's small ringing on
    /// its stop is left and write that ringing in closed form (`ringing_tail.rs`). Extension.
    pub ringing_tail: bool,
}

/// `[energy]`: the energy ledger.
#[derive(Clone, Debug, PartialEq)]
pub struct Energy {
    /// `energy.ledger`: integrate robot work and dissipations (extra states). Extension.
    pub ledger: bool,
}

/// A scene: every key of SPEC section 7 with its default.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// `module`: `"hydraulic"`, `"bistable"` or `"rigid"`.
    pub module: Module,
    /// `t_end`: end of simulated time, s (> 0).
    pub t_end: f64,
    pub robot: Robot,
    pub tool: Tool,
    pub object: Object,
    pub stops: Stops,
    pub hydraulic: Hydraulic,
    pub bistable: Bistable,
    pub solver: Solver,
    pub energy: Energy,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            module: Module::Hydraulic,
            t_end: 0.3,
            robot: Robot {
                approach_speed: 1.0,
                brake_deceleration: 10.0,
                dead_time: 0.070,
                start: RobotStart::Cruising,
                acceleration: 10.0,
            },
            tool: Tool {
                mass: 0.048,
                sensor_threshold: 1.5e-3,
                viscous_friction: 0.5,
                dry_friction: 0.0,
            },
            object: Object {
                enabled: true,
                mass: 0.246,
                gap: 1e-3,
                contact_stiffness: 0.6e6,
                contact_damping: 1.35e6,
                plane_friction: 0.0,
            },
            stops: Stops {
                stroke: 0.023,
                stiffness: 0.6e6,
                damping: 1.35e6,
            },
            hydraulic: Hydraulic {
                piston_radius: 0.020,
                orifice_radius: 0.008,
                loss_coefficient: 3.0,
                liquid_density: 900.0,
                gas_pressure: 1000.0,
                gas_volume: 7.63e-5,
                gas_exponent: 1.4,
                cavitation: false,
                cavitation_pressure: 0.0,
                bulk_modulus: 0.0,
                chamber_volume: 4.0e-5,
            },
            bistable: Bistable {
                spring_stiffness: 7022.0,
                half_span: 0.030,
                apex_rise: 0.0125,
                offset: 0.001,
            },
            solver: Solver {
                method: Method::Dp5,
                rtol: 1e-6,
                atol: 1e-9,
                max_steps: 1_000_000,
                fixed_step: 1e-5,
                stiffness: StiffnessAction::Warn,
                early_end: true,
                ringing_tail: true,
            },
            energy: Energy { ledger: true },
        }
    }
}

/// A value type a key can hold: conversion from and to TOML, and its name in messages.
trait KeyValue: Sized {
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

fn format_float(f: f64) -> String {
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
        choice(key, v, &["dp5", "rk4", "euler"], Method::from_name)
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

/// One key a user may type: its name, its SI unit and what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyInfo {
    /// `section.name` (or `module`, `t_end`).
    pub key: &'static str,
    /// SI unit: `"s"`, `"m"`, `"N/m^1.5"`, ...; `"-"` for a dimensionless number, `""` for a
    /// choice of words or a switch (and for `solver.atol`, which applies to every state in its own
    /// unit).
    pub unit: &'static str,
    /// One line in a user's words, with the symbol of SPEC and the allowed values.
    pub description: &'static str,
}

macro_rules! scene_keys {
    ($( $key:literal => $($field:ident).+ , $unit:literal , $description:literal ; )*) => {
        const KEY_LIST: &[&str] = &[$($key),*];

        const KEY_INFO: &[KeyInfo] = &[$(KeyInfo {
            key: $key,
            unit: $unit,
            description: $description,
        }),*];

        impl Scene {
            fn set_field(&mut self, key: &str, v: &toml::Value) -> Result<(), ConfigError> {
                match key {
                    $( $key => { self.$($field).+ = KeyValue::from_value(key, v)?; Ok(()) } )*
                    _ => Err(unknown_key(key)),
                }
            }
            fn get_field(&self, key: &str) -> Option<toml::Value> {
                match key {
                    $( $key => Some(KeyValue::to_value(&self.$($field).+)), )*
                    _ => None,
                }
            }
        }
    };
}

// key => field, unit, description
scene_keys! {
    "module" => module, "",
        "compliance module between flange and tool: \"hydraulic\", \"bistable\" or \"rigid\" (tool bolted to the flange)";
    "t_end" => t_end, "s",
        "end of simulated time (> 0)";
    "robot.approach_speed" => robot.approach_speed, "m/s",
        "v_max: flange speed before the impact (> 0)";
    "robot.brake_deceleration" => robot.brake_deceleration, "m/s^2",
        "a_brake: deceleration of the robot once it brakes, until it stands (> 0)";
    "robot.dead_time" => robot.dead_time, "s",
        "DT: delay from the impact sensor switching (rigid: first contact) to the start of braking (>= 0)";
    "robot.start" => robot.start, "",
        "how the robot starts: \"cruising\" (moving at v_max at t = 0) or \"rest\" (accelerating at robot.acceleration)";
    "robot.acceleration" => robot.acceleration, "m/s^2",
        "a_acc: acceleration from rest up to v_max, with robot.start = \"rest\" only (> 0)";
    "tool.mass" => tool.mass, "kg",
        "m_t: mass of the tool, the end-effector (> 0)";
    "tool.sensor_threshold" => tool.sensor_threshold, "m",
        "s_sensor: stroke at which the impact sensor switches, inside (0, stops.stroke)";
    "tool.viscous_friction" => tool.viscous_friction, "kg/s",
        "b: viscous friction between tool and module, force b times their sliding speed (>= 0)";
    "tool.dry_friction" => tool.dry_friction, "N",
        "d: Coulomb (dry) friction force between tool and module; > 0 adds stick-slip (>= 0)";
    "object.enabled" => object.enabled, "",
        "true: an object lies on the plane; false: no object (free tool, no contact)";
    "object.mass" => object.mass, "kg",
        "m_p: mass of the object (> 0)";
    "object.gap" => object.gap, "m",
        "initial distance from the tool's face to the object's face (> 0)";
    "object.contact_stiffness" => object.contact_stiffness, "N/m^1.5",
        "k_c: Hunt-Crossley stiffness of the tool-object contact (> 0)";
    "object.contact_damping" => object.contact_damping, "N s/m^2.5",
        "chi_c: Hunt-Crossley damping of the tool-object contact (>= 0)";
    "object.plane_friction" => object.plane_friction, "-",
        "mu_plane: Coulomb friction coefficient between object and plane; 0 = off (>= 0)";
    "stops.stroke" => stops.stroke, "m",
        "L: stroke, the distance between the module's forward and back end-stops (> 0)";
    "stops.stiffness" => stops.stiffness, "N/m^1.5",
        "k_e: Hunt-Crossley stiffness of both end-stops (> 0)";
    "stops.damping" => stops.damping, "N s/m^2.5",
        "chi_e: Hunt-Crossley damping of both end-stops (>= 0)";
    "hydraulic.piston_radius" => hydraulic.piston_radius, "m",
        "R_p: radius of the main cylinder's piston (> 0)";
    "hydraulic.orifice_radius" => hydraulic.orifice_radius, "m",
        "R_o: radius of the orifice between main and auxiliary cylinder, in (0, R_p)";
    "hydraulic.loss_coefficient" => hydraulic.loss_coefficient, "-",
        "c0: loss coefficient of the orifice (> 0)";
    "hydraulic.liquid_density" => hydraulic.liquid_density, "kg/m^3",
        "rho_L: density of the hydraulic liquid (> 0)";
    "hydraulic.gas_pressure" => hydraulic.gas_pressure, "Pa",
        "p10: gas pressure with the tool on its forward stop (stroke s = 0) (> 0)";
    "hydraulic.gas_volume" => hydraulic.gas_volume, "m^3",
        "V_g0: gas volume with the tool on its forward stop (s = 0); must exceed the stroke's volume A_p * L";
    "hydraulic.gas_exponent" => hydraulic.gas_exponent, "-",
        "kappa: adiabatic exponent of the gas, in (1, 2]";
    "hydraulic.cavitation" => hydraulic.cavitation, "",
        "true: the main chamber pressure cannot fall below hydraulic.cavitation_pressure";
    "hydraulic.cavitation_pressure" => hydraulic.cavitation_pressure, "Pa",
        "p_cav: lowest main chamber pressure with hydraulic.cavitation on, below hydraulic.gas_pressure";
    "hydraulic.bulk_modulus" => hydraulic.bulk_modulus, "Pa",
        "beta: bulk modulus of the liquid; 0 = incompressible (lumped model), > 0 = compressible model (stiff; about 1.5e9 for oil)";
    "hydraulic.chamber_volume" => hydraulic.chamber_volume, "m^3",
        "V_m0: liquid volume of the main chamber at s = 0, used with hydraulic.bulk_modulus > 0; must exceed A_p * L";
    "bistable.spring_stiffness" => bistable.spring_stiffness, "N/m",
        "k_b: stiffness of each of the two springs of the snap-through element (> 0)";
    "bistable.half_span" => bistable.half_span, "m",
        "w: half span of the snap-through element (> 0)";
    "bistable.apex_rise" => bistable.apex_rise, "m",
        "h: apex rise of the snap-through element; stable at 0 and 2h (> 0)";
    "bistable.offset" => bistable.offset, "m",
        "e: distance from the element's first stable point to the forward stop, which preloads the tool onto that stop, in [0, h)";
    "solver.method" => solver.method, "",
        "integration method: \"dp5\" (adaptive Dormand-Prince 5(4)), \"rk4\" or \"euler\" (fixed step solver.fixed_step)";
    "solver.rtol" => solver.rtol, "-",
        "relative tolerance of the adaptive method, in (2.2e-15, 1)";
    "solver.atol" => solver.atol, "",
        "absolute tolerance of the adaptive method, applied to every state in its own SI unit (> 0)";
    "solver.max_steps" => solver.max_steps, "-",
        "most solver steps before the run ends with status max_steps (>= 1)";
    "solver.fixed_step" => solver.fixed_step, "s",
        "step size of the fixed-step methods \"rk4\" and \"euler\" (> 0)";
    "solver.stiffness" => solver.stiffness, "",
        "what Hairer's stiffness test does when it fires: \"warn\" (flag it), \"stop\" (status stiff) or \"off\"";
    "solver.early_end" => solver.early_end, "",
        "true: end the run once nothing can change any more (results extrapolated to t_end)";
    "solver.ringing_tail" => solver.ringing_tail, "",
        "true (with solver.early_end): once only the tool's small ringing on its stop is left, write it in closed form";
    "energy.ledger" => energy.ledger, "",
        "true: integrate robot work and dissipations for the energy ledger (extra states)";
}

const SECTIONS: &[&str] = &[
    "robot",
    "tool",
    "object",
    "stops",
    "hydraulic",
    "bistable",
    "solver",
    "energy",
];

fn unknown_key(key: &str) -> ConfigError {
    // Name the keys of the same section when the section is known, else every key.
    let section = key.split('.').next().unwrap_or("");
    let same: Vec<&str> = if key.contains('.') && SECTIONS.contains(&section) {
        KEY_LIST
            .iter()
            .copied()
            .filter(|k| k.starts_with(&format!("{section}.")))
            .collect()
    } else {
        KEY_LIST.to_vec()
    };
    ConfigError::UnknownKey {
        key: key.into(),
        allowed: same.join(", "),
    }
}

fn invalid(key: &str, value: f64, allowed: impl Into<String>) -> ConfigError {
    ConfigError::InvalidValue {
        key: key.into(),
        value: format_float(value),
        allowed: allowed.into(),
    }
}

/// Parse `text` as one TOML value (`1e-3`, `true`, `"x"`, `[1, 2]`); a bare word that is not
/// TOML (`bistable`) is taken as a string.
pub fn parse_value(text: &str) -> toml::Value {
    let t = text.trim();
    if let Ok(table) = format!("v = {t}").parse::<toml::Table>() {
        if table.len() == 1 {
            if let Some(v) = table.get("v") {
                return v.clone();
            }
        }
    }
    toml::Value::String(t.to_string())
}

impl Scene {
    /// Parse a scene from TOML text (unknown keys and wrong types are errors); not validated.
    /// Keys missing from the text keep their defaults.
    pub fn from_toml_str(text: &str) -> Result<Scene, ConfigError> {
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            let mut message = format!("TOML syntax error: {}", e.message());
            if let Some(span) = e.span() {
                let upto = &text[..span.start.min(text.len())];
                let line = upto.matches('\n').count() + 1;
                let col = upto.len() - upto.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
                message = format!("line {line}, column {col}: {message}");
            }
            ConfigError::File {
                path: "<scene>".into(),
                message,
            }
        })?;
        let mut scene = Scene::default();
        scene.apply_table(&table)?;
        Ok(scene)
    }

    /// Apply every key of a TOML table (sections as sub-tables, or dotted keys).
    pub fn apply_table(&mut self, table: &toml::Table) -> Result<(), ConfigError> {
        for (k, v) in table {
            match v {
                toml::Value::Table(sub) if SECTIONS.contains(&k.as_str()) => {
                    for (name, value) in sub {
                        let key = format!("{k}.{name}");
                        if let toml::Value::Table(_) = value {
                            return Err(unknown_key(&key));
                        }
                        self.set(&key, value)?;
                    }
                }
                toml::Value::Table(_) => return Err(unknown_key(k)),
                _ => self.set(k, v)?,
            }
        }
        Ok(())
    }

    /// Read and parse a scene file; errors name the path.
    pub fn from_file(path: &std::path::Path) -> Result<Scene, ConfigError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::File {
            path: p.clone(),
            message: format!("cannot read scene file: {e}"),
        })?;
        match Scene::from_toml_str(&text) {
            Err(ConfigError::File { message, .. }) => Err(ConfigError::File { path: p, message }),
            other => other,
        }
    }

    /// Set one key (`section.name`) to a TOML value (a float key also takes an integer).
    pub fn set(&mut self, key: &str, value: &toml::Value) -> Result<(), ConfigError> {
        self.set_field(key, value)
    }

    /// Set one key from the text of `--set KEY=VALUE` (parsed as a TOML value; a bare word is a
    /// string, so `module=bistable` works).
    pub fn set_from_str(&mut self, key: &str, text: &str) -> Result<(), ConfigError> {
        if !KEY_LIST.contains(&key) {
            return Err(unknown_key(key));
        }
        self.set(key, &parse_value(text))
    }

    /// The value of one key.
    pub fn get(&self, key: &str) -> Result<toml::Value, ConfigError> {
        self.get_field(key).ok_or_else(|| unknown_key(key))
    }

    /// Every key a user may type, in SPEC order (extensions beside their section).
    pub fn keys() -> &'static [&'static str] {
        KEY_LIST
    }

    /// Every key's unit and description, in the order of [`Scene::keys`]
    /// (`docs/scene-keys.md` is this table with the defaults).
    pub fn key_info() -> &'static [KeyInfo] {
        KEY_INFO
    }

    /// The scene as a TOML table (every key, for provenance): `module` and `t_end` at the top,
    /// one sub-table per section.
    pub fn to_toml(&self) -> toml::Table {
        let mut top = toml::Table::new();
        for key in KEY_LIST {
            let v = self.get_field(key).expect("every listed key has a field");
            match key.split_once('.') {
                None => {
                    top.insert((*key).into(), v);
                }
                Some((sec, name)) => {
                    let entry = top
                        .entry(sec.to_string())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                    if let toml::Value::Table(t) = entry {
                        t.insert(name.into(), v);
                    }
                }
            }
        }
        top
    }

    /// Piston area `A_p = pi R_p^2`, m^2.
    pub fn piston_area(&self) -> f64 {
        std::f64::consts::PI * self.hydraulic.piston_radius.powi(2)
    }
    /// Orifice area `A_o = pi R_o^2`, m^2.
    pub fn orifice_area(&self) -> f64 {
        std::f64::consts::PI * self.hydraulic.orifice_radius.powi(2)
    }
}
