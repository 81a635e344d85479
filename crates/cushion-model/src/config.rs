//! Scene files: the keys of `docs/scene-keys.md`, their defaults, units and checks.
//!
//! A scene file is TOML. Top-level keys are `module` and `t_end`; every other key lives in a
//! section (`[robot]`, `[tool]`, `[object]`, `[stops]`, `[hydraulic]`, `[bistable]`,
//! `[solver]`, `[energy]`) and is addressed as `section.name` everywhere (`--set`, sweep axes,
//! Python keyword overrides). All values are SI; no unit is ever part of a key.
//!
//! Extensions beyond the paper's model (all optional, with defaults that leave that model as it
//! is; `docs/scene-keys.md`):
//! `object.enabled`, `energy.ledger`, `solver.max_steps`, `solver.fixed_step`,
//! `solver.stiffness`, `solver.early_end`, `solver.ringing_tail`, `hydraulic.cavitation`,
//! `hydraulic.cavitation_pressure`, `hydraulic.bulk_modulus`, `hydraulic.chamber_volume`,
//! `hydraulic.kinematic_viscosity`, `hydraulic.critical_reynolds`.
//!
//! Every key's unit and description live in one list, the `scene_keys!` invocation below;
//! [`Scene::key_info`] returns it, and `docs/scene-keys.md` is its table with the defaults (a
//! test keeps that page current).
//!
//! Parsing never validates combinations; [`Scene::validate`] does (and `simulate` calls it).
//! Every error names the key, the value and what is allowed.

mod keys;
mod validate;
mod values;

pub use keys::{parse_value, KeyInfo};
pub use values::stiffness_name;

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

/// `[robot]`: the prescribed flange motion (`docs/model.md`, section "Robot").
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

/// `[hydraulic]`: the hydraulic module (`docs/model.md`, section "Hydraulic module").
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
    /// incompressible model (`docs/model.md`, "Hydraulic module"); > 0: the richer model
    /// ("Compressible liquid"), with the
    /// main chamber pressure `p_m` and the volume moved through the orifice as states (stiff;
    /// about 1.5e9 for oil). Extension.
    pub bulk_modulus: f64,
    /// `hydraulic.chamber_volume`: liquid volume of the main chamber at `s = 0`, m^3 (>
    /// `A_p * L`), or 0 (the default): the piston's swept volume `A_p * L` plus
    /// [`DEAD_VOLUME`], so that it follows the geometry ([`Scene::main_chamber_volume`]). Used
    /// only with `bulk_modulus > 0`. Extension.
    pub chamber_volume: f64,
    /// `hydraulic.kinematic_viscosity`: `nu`, of the liquid, m^2/s (> 0; 3.2e-5 for an ISO VG
    /// 32 hydraulic oil at 40 C). With `critical_reynolds` it sets where the compressible
    /// model's orifice turns laminar. Extension.
    pub kinematic_viscosity: f64,
    /// `hydraulic.critical_reynolds`: `Re_cr`, the orifice's Reynolds number below which its
    /// flow is laminar, - (> 0; 12, as Simscape Fluids' local restrictions; Merritt gives 10
    /// or so for sharp-edged orifices). Compressible model only. Extension.
    pub critical_reynolds: f64,
}

/// Liquid in the main chamber beyond the piston's swept volume when `hydraulic.chamber_volume`
/// is 0, m^3: the paper's geometry (`A_p L` = 2.89e-5 m^3) then holds about 4.0e-5 m^3 at
/// `s = 0`.
pub const DEAD_VOLUME: f64 = 1.11e-5;

/// `[bistable]`: the von Mises snap-through element (`docs/model.md`, section "Bistable module").
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
    /// `solver.method`: `"auto"` (the default: DOPRI5 while the scene is not stiff, Rodas while
    /// it is), `"dp5"`, `"dop853"`, `"rodas"` (adaptive), `"rk4"` or `"euler"` (fixed step).
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
    /// its stop is left and write that ringing in closed form (`early_end/ringing_search.rs`). Extension.
    pub ringing_tail: bool,
}

/// `[energy]`: the energy ledger.
#[derive(Clone, Debug, PartialEq)]
pub struct Energy {
    /// `energy.ledger`: integrate robot work and dissipations (extra states). Extension.
    pub ledger: bool,
}

/// A scene: every key of `docs/scene-keys.md` with its default.
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
                chamber_volume: 0.0,
                kinematic_viscosity: 3.2e-5,
                critical_reynolds: 12.0,
            },
            bistable: Bistable {
                spring_stiffness: 7022.0,
                half_span: 0.030,
                apex_rise: 0.0125,
                offset: 0.001,
            },
            solver: Solver {
                method: Method::Auto,
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
