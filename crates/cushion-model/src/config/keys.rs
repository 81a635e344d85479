//! The table of scene keys (name, field, unit, description) and what is done by key: set, get,
//! parse a scene file or a `--set` value, write the scene back as TOML.

use super::values::{format_float, KeyValue};
use super::*;

/// One key a user may type: its name, its SI unit and what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyInfo {
    /// `section.name` (or `module`, `t_end`).
    pub key: &'static str,
    /// SI unit: `"s"`, `"m"`, `"N/m^1.5"`, ...; `"-"` for a dimensionless number, `""` for a
    /// choice of words or a switch (and for `solver.atol`, which applies to every state in its own
    /// unit).
    pub unit: &'static str,
    /// One line in a user's words, with the symbol of `docs/model.md` and the allowed values.
    pub description: &'static str,
}

macro_rules! scene_keys {
    ($( $key:literal => $($field:ident).+ , $unit:literal , $description:literal ; )*) => {
        pub(super) const KEY_LIST: &[&str] = &[$($key),*];

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
            pub(super) fn get_field(&self, key: &str) -> Option<toml::Value> {
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
        "V_m0: liquid volume of the main chamber at s = 0, used with hydraulic.bulk_modulus > 0; must exceed A_p * L; 0: A_p * L plus a dead volume of 1.11e-5 m^3";
    "hydraulic.kinematic_viscosity" => hydraulic.kinematic_viscosity, "m^2/s",
        "nu: kinematic viscosity of the liquid (> 0); with hydraulic.critical_reynolds, where the compressible model's orifice turns laminar";
    "hydraulic.critical_reynolds" => hydraulic.critical_reynolds, "-",
        "Re_cr: the orifice's Reynolds number below which its flow is laminar (> 0), compressible model";
    "bistable.spring_stiffness" => bistable.spring_stiffness, "N/m",
        "k_b: stiffness of each of the two springs of the snap-through element (> 0)";
    "bistable.half_span" => bistable.half_span, "m",
        "w: half span of the snap-through element (> 0)";
    "bistable.apex_rise" => bistable.apex_rise, "m",
        "h: apex rise of the snap-through element; stable at 0 and 2h (> 0)";
    "bistable.offset" => bistable.offset, "m",
        "e: distance from the element's first stable point to the forward stop, which preloads the tool onto that stop, in [0, h)";
    "solver.method" => solver.method, "",
        "integration method: \"auto\" (dp5 while the scene is not stiff, rodas while it is; dp5's steps to the bit on a scene that is never stiff), \"dp5\" (adaptive Dormand-Prince 5(4)), \"dop853\" (adaptive Dormand-Prince 8(5,3), Hairer's DOP853, for tight tolerances), \"rodas\" (adaptive implicit Rosenbrock Rodas4 with the model's exact Jacobian, for stiff scenes), \"rk4\" or \"euler\" (fixed step solver.fixed_step)";
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

pub(super) fn invalid(key: &str, value: f64, allowed: impl Into<String>) -> ConfigError {
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

    /// Every key a user may type, section by section as `docs/scene-keys.md` lists them (`module`,
    /// `t_end`, robot, tool, object, stops, hydraulic, bistable, solver, energy; extensions beside
    /// their section).
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
    /// The main chamber's liquid volume at `s = 0` for the compressible model, m^3:
    /// `hydraulic.chamber_volume`, or, when that is 0, the piston's swept volume `A_p L` plus
    /// [`DEAD_VOLUME`](super::DEAD_VOLUME).
    pub fn main_chamber_volume(&self) -> f64 {
        if self.hydraulic.chamber_volume > 0.0 {
            self.hydraulic.chamber_volume
        } else {
            self.piston_area() * self.stops.stroke + super::DEAD_VOLUME
        }
    }

    /// Orifice area `A_o = pi R_o^2`, m^2.
    pub fn orifice_area(&self) -> f64 {
        std::f64::consts::PI * self.hydraulic.orifice_radius.powi(2)
    }
}
