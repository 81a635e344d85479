//! Validation of a scene: every value in its range and every combination consistent (ranges in
//! `docs/scene-keys.md`; combinations in `docs/model.md`, the "Validation" paragraph), refused
//! with a message that names the key, the value and what is allowed.

use super::keys::{invalid, KEY_LIST};
use super::values::format_float;
use super::{ConfigError, Module, Scene, DEAD_VOLUME};
use crate::physics;

impl Scene {
    /// Check every value and every combination (positive masses, orifice smaller than piston,
    /// gas volume positive over the stroke, sensor inside the stroke, ...). Every number must be
    /// finite; beyond that, a part's keys constrain only the scenes that have the part: the
    /// stops and the sensor a module with a sliding tool, the hydraulic section a hydraulic
    /// scene (the compressible liquid's chamber volume only with `bulk_modulus > 0`, the
    /// cavitation pressure only with cavitation), the bistable section a bistable scene, the
    /// object a scene with an object. A sweep checks every run's own scene before its first
    /// run, so a sweep that switches `module` still meets no invalid run at run time
    /// (`tests/model/config.rs::a_part_constrains_only_the_scenes_that_have_it`).
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_numbers_are_finite()?;
        positive("t_end", self.t_end)?;
        self.validate_robot()?;
        self.validate_tool()?;
        if self.object.enabled {
            self.validate_object()?;
        }
        if self.module != Module::Rigid {
            self.validate_stops_and_sensor()?;
        }
        if self.module == Module::Hydraulic {
            self.validate_hydraulic()?;
        }
        if self.module == Module::Bistable {
            self.validate_bistable()?;
        }
        self.validate_solver()
    }

    /// Every number of the scene is finite, whatever part it belongs to.
    fn validate_numbers_are_finite(&self) -> Result<(), ConfigError> {
        for key in KEY_LIST {
            if let Some(toml::Value::Float(f)) = self.get_field(key) {
                if !f.is_finite() {
                    return Err(invalid(key, f, "must be a finite number"));
                }
            }
        }
        Ok(())
    }

    /// The robot's approach speed, braking, dead time and acceleration from rest.
    fn validate_robot(&self) -> Result<(), ConfigError> {
        positive("robot.approach_speed", self.robot.approach_speed)?;
        positive("robot.brake_deceleration", self.robot.brake_deceleration)?;
        non_negative("robot.dead_time", self.robot.dead_time)?;
        positive("robot.acceleration", self.robot.acceleration)
    }

    /// The tool's mass and friction.
    fn validate_tool(&self) -> Result<(), ConfigError> {
        positive("tool.mass", self.tool.mass)?;
        non_negative("tool.viscous_friction", self.tool.viscous_friction)?;
        non_negative("tool.dry_friction", self.tool.dry_friction)
    }

    /// The object, its contact with the tool and its friction on the plane.
    fn validate_object(&self) -> Result<(), ConfigError> {
        positive("object.mass", self.object.mass)?;
        positive("object.gap", self.object.gap)?;
        positive("object.contact_stiffness", self.object.contact_stiffness)?;
        non_negative("object.contact_damping", self.object.contact_damping)?;
        non_negative("object.plane_friction", self.object.plane_friction)
    }

    /// The end-stops of a sliding tool, and its sensor, which must switch inside the stroke.
    fn validate_stops_and_sensor(&self) -> Result<(), ConfigError> {
        let l = self.stops.stroke;
        positive("stops.stroke", self.stops.stroke)?;
        positive("stops.stiffness", self.stops.stiffness)?;
        non_negative("stops.damping", self.stops.damping)?;
        let ss = self.tool.sensor_threshold;
        if !(ss > 0.0 && ss < l) {
            return Err(invalid(
                "tool.sensor_threshold",
                ss,
                format!(
                    "must lie inside the stroke, 0 < s_sensor < stops.stroke = {}",
                    format_float(l)
                ),
            ));
        }
        Ok(())
    }

    /// The hydraulic module: the orifice smaller than the piston, the gas volume and (with a
    /// compressible liquid) the main chamber positive over the whole stroke, the polytropic
    /// exponent in (1, 2], the cavitation pressure below the gas's.
    fn validate_hydraulic(&self) -> Result<(), ConfigError> {
        let l = self.stops.stroke;
        let h = &self.hydraulic;
        positive("hydraulic.piston_radius", h.piston_radius)?;
        positive("hydraulic.orifice_radius", h.orifice_radius)?;
        if h.orifice_radius >= h.piston_radius {
            return Err(invalid(
                "hydraulic.orifice_radius",
                h.orifice_radius,
                format!(
                    "the orifice must be smaller than the piston: must be < hydraulic.piston_radius = {}",
                    format_float(h.piston_radius)
                ),
            ));
        }
        positive("hydraulic.loss_coefficient", h.loss_coefficient)?;
        positive("hydraulic.liquid_density", h.liquid_density)?;
        positive("hydraulic.gas_pressure", h.gas_pressure)?;
        positive("hydraulic.gas_volume", h.gas_volume)?;
        let a_p = std::f64::consts::PI * h.piston_radius * h.piston_radius;
        if h.gas_volume - a_p * l <= 0.0 {
            return Err(invalid(
                "hydraulic.gas_volume",
                h.gas_volume,
                format!(
                    "the gas volume V_g0 - A_p*s reaches zero inside the stroke: must be > A_p * stops.stroke = {} m^3",
                    format_float(a_p * l)
                ),
            ));
        }
        let k = h.gas_exponent;
        if !(k > 1.0 && k <= 2.0) {
            return Err(invalid("hydraulic.gas_exponent", k, "must lie in (1, 2]"));
        }
        non_negative("hydraulic.bulk_modulus", h.bulk_modulus)?;
        non_negative("hydraulic.chamber_volume", h.chamber_volume)?;
        if h.bulk_modulus > 0.0 && self.main_chamber_volume() - a_p * l <= 0.0 {
            return Err(invalid(
                "hydraulic.chamber_volume",
                h.chamber_volume,
                format!(
                    "the piston would fill the main chamber inside the stroke: must be > A_p * stops.stroke = {} m^3 (or 0: the swept volume plus {} m^3)",
                    format_float(a_p * l),
                    format_float(DEAD_VOLUME)
                ),
            ));
        }
        if h.bulk_modulus > 0.0 {
            positive("hydraulic.kinematic_viscosity", h.kinematic_viscosity)?;
            positive("hydraulic.critical_reynolds", h.critical_reynolds)?;
        }
        if h.cavitation && h.cavitation_pressure >= h.gas_pressure {
            return Err(invalid(
                "hydraulic.cavitation_pressure",
                h.cavitation_pressure,
                format!(
                    "must be < hydraulic.gas_pressure = {}",
                    format_float(h.gas_pressure)
                ),
            ));
        }
        Ok(())
    }

    /// The bistable module: its springs and geometry, the offset below the apex, and forces
    /// that stay finite numbers.
    fn validate_bistable(&self) -> Result<(), ConfigError> {
        let b = &self.bistable;
        positive("bistable.spring_stiffness", b.spring_stiffness)?;
        positive("bistable.half_span", b.half_span)?;
        positive("bistable.apex_rise", b.apex_rise)?;
        if !(b.offset >= 0.0 && b.offset < b.apex_rise) {
            return Err(invalid(
                "bistable.offset",
                b.offset,
                format!(
                    "must lie in [0, bistable.apex_rise = {})",
                    format_float(b.apex_rise)
                ),
            ));
        }
        self.bistable_forces_are_finite()
    }

    /// The solver's tolerances and step limits.
    fn validate_solver(&self) -> Result<(), ConfigError> {
        let s = &self.solver;
        // Hairer's DOPRI5 refuses rtol <= 10 eps (no step can meet it); 1 or more asks for no
        // digit at all
        if !(s.rtol > 10.0 * f64::EPSILON && s.rtol < 1.0) {
            return Err(invalid(
                "solver.rtol",
                s.rtol,
                "must lie in (10 eps = 2.2e-15, 1)",
            ));
        }
        positive("solver.atol", s.atol)?;
        if s.max_steps < 1 {
            return Err(ConfigError::InvalidValue {
                key: "solver.max_steps".into(),
                value: s.max_steps.to_string(),
                allowed: "must be >= 1".into(),
            });
        }
        positive("solver.fixed_step", s.fixed_step)
    }

    /// The von Mises element's force and energy stay finite numbers over the stroke and at its
    /// preload equilibrium on the forward stop, as `Model::new` finds it. Finite values large
    /// enough to overflow there would otherwise start a run from a state or a slope that is not
    /// a number: a half span of 1e200 m (`w^2` overflows), or a spring of 1e300 N/m, whose
    /// preload of 2.7e296 N brackets the equilibrium by 5.8e193 m; the root search's 200
    /// bisections of that bracket end at a depth of 1.8e133 m, where the force is infinite.
    fn bistable_forces_are_finite(&self) -> Result<(), ConfigError> {
        let b = &self.bistable;
        let (k_b, w, h, e) = (b.spring_stiffness, b.half_span, b.apex_rise, b.offset);
        if !(w * w + h * h).is_finite() {
            let (key, v) = if w >= h {
                ("bistable.half_span", w)
            } else {
                ("bistable.apex_rise", h)
            };
            return Err(invalid(
                key,
                v,
                "must keep the spring length sqrt(w^2 + h^2) a finite number (w and h below 1e154 m)",
            ));
        }
        let k_e = self.stops.stiffness;
        let s0 = physics::preload_equilibrium(k_e, |s| physics::bistable_force(k_b, w, h, s + e));
        let finite = |s: f64| {
            let x = s + e;
            physics::bistable_force(k_b, w, h, x).is_finite()
                && physics::bistable_energy(k_b, w, h, x).is_finite()
        };
        let stop_force = k_e * s0.abs() * s0.abs().sqrt();
        if !(s0.is_finite()
            && stop_force.is_finite()
            && [s0, 0.0, self.stops.stroke].into_iter().all(finite))
        {
            // the two stiffnesses set the preload's depth: name the one further from its
            // default (in orders of magnitude), and the other in the message
            let d = Scene::default();
            let off = |v: f64, v0: f64| (v / v0).log10().abs();
            let (spring, stop) = (
                ("bistable.spring_stiffness", k_b, "a smaller"),
                ("stops.stiffness", k_e, "a larger"),
            );
            let ((key, v, fix), (other, other_v, _)) =
                if off(k_b, d.bistable.spring_stiffness) >= off(k_e, d.stops.stiffness) {
                    (spring, stop)
                } else {
                    (stop, spring)
                };
            return Err(invalid(
                key,
                v,
                format!(
                    "must keep the bistable springs' force and energy finite numbers over the stroke and at their preload equilibrium on the forward stop (with {other} = {}): {fix} value",
                    format_float(other_v)
                ),
            ));
        }
        Ok(())
    }
}

/// `v` must be > 0.
fn positive(key: &str, v: f64) -> Result<(), ConfigError> {
    if v > 0.0 {
        Ok(())
    } else {
        Err(invalid(key, v, "must be > 0"))
    }
}

/// `v` must be >= 0.
fn non_negative(key: &str, v: f64) -> Result<(), ConfigError> {
    if v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(key, v, "must be >= 0"))
    }
}
