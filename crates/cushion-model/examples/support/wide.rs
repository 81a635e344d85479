//! Random scenes far outside the paper's: every key of SPEC section 7 over a wide range.
//! Shared by `examples/wide_scenes.rs` (many scenes, a report) and `tests/wide_scenes.rs`.

use super::Uniform;
use cushion_model::config::RobotStart;
use cushion_model::{simulate, Module, RunOptions, RunResult, Scene, Summary};

/// The leading `N SEED` arguments of the wide-scene examples (defaults 1000 and one fixed seed),
/// so that `wide_scenes` and `wide_accuracy` draw the same scenes from the same arguments.
pub fn count_and_seed(args: &mut impl Iterator<Item = String>) -> (usize, u64) {
    let n = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let seed = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(0x5DEECE66D);
    (n, seed)
}

/// A run with its trajectory recorded as a user plots it: every step, every event, and samples
/// every `t_end / 2000`.
pub fn run_recorded(s: &Scene) -> RunResult {
    simulate(
        s,
        &RunOptions {
            trajectory: true,
            sample_interval: Some(s.t_end / 2000.0),
        },
    )
}

/// A run's impact counts: tool-object, forward stop, back stop.
pub fn impact_counts(s: &Summary) -> (u32, u32, u32) {
    (
        s.object_impacts,
        s.forward_stop_impacts,
        s.back_stop_impacts,
    )
}

impl Uniform {
    /// Uniform in `[lo, hi)`.
    pub fn between(&mut self, lo: f64, hi: f64) -> f64 {
        self.span(lo, hi - lo)
    }
}

/// How often the rarer corners come up: the compressible liquid (stiff: an explicit method
/// takes up to its step limit there), fixed-step methods, a low step limit, the stiffness test
/// stopping the run.
#[derive(Clone, Copy)]
pub struct Corners {
    pub compressible: f64,
    pub fixed_step: f64,
    pub step_limit: f64,
    pub stiffness_stop: f64,
}

impl Corners {
    pub const NONE: Corners = Corners {
        compressible: 0.0,
        fixed_step: 0.0,
        step_limit: 0.0,
        stiffness_stop: 0.0,
    };
    pub const SOME: Corners = Corners {
        compressible: 0.02,
        fixed_step: 0.02,
        step_limit: 0.01,
        stiffness_stop: 0.01,
    };
}

/// One random scene over wide ranges (valid by construction, apart from rare corner cases
/// that `validate` may still refuse).
pub fn draw(u: &mut Uniform, corners: Corners) -> Scene {
    let module = match (u.next() * 3.0) as u32 {
        0 => Module::Hydraulic,
        1 => Module::Bistable,
        _ => Module::Rigid,
    };
    let mut s = Scene {
        module,
        t_end: u.between(0.05, 0.95),
        ..Scene::default()
    };
    let r = &mut s.robot;
    r.approach_speed = u.log_between(0.05, 3.0);
    r.brake_deceleration = u.log_between(1.0, 100.0);
    r.dead_time = u.between(0.0, 0.2);
    if u.next() < 0.3 {
        r.start = RobotStart::Rest;
        r.acceleration = u.log_between(1.0, 100.0);
    }
    s.stops.stroke = u.between(0.005, 0.045);
    s.stops.stiffness = u.log_between(1e4, 1e8);
    s.stops.damping = s.stops.stiffness * u.log_between(0.1, 10.0);
    let t = &mut s.tool;
    t.mass = u.log_between(0.005, 1.0);
    t.sensor_threshold = s.stops.stroke * u.between(0.02, 0.9);
    t.viscous_friction = if u.next() < 0.5 {
        0.0
    } else {
        u.between(0.0, 5.0)
    };
    t.dry_friction = if u.next() < 0.7 {
        0.0
    } else {
        u.between(0.0, 2.0)
    };
    let o = &mut s.object;
    o.enabled = u.next() < 0.9;
    o.mass = u.log_between(0.01, 1.0);
    o.gap = u.between(0.0, 0.005);
    o.contact_stiffness = u.log_between(1e4, 1e8);
    o.contact_damping = o.contact_stiffness * u.log_between(0.1, 10.0);
    o.plane_friction = if u.next() < 0.7 {
        0.0
    } else {
        u.between(0.0, 1.0)
    };
    let h = &mut s.hydraulic;
    h.piston_radius = u.between(0.01, 0.03);
    h.orifice_radius = h.piston_radius * u.between(0.05, 0.9);
    h.loss_coefficient = u.between(0.5, 5.0);
    h.liquid_density = u.between(700.0, 1300.0);
    h.gas_pressure = u.log_between(100.0, 1e6);
    let swept = std::f64::consts::PI * h.piston_radius.powi(2) * s.stops.stroke;
    h.gas_volume = swept * u.log_between(1.2, 30.0);
    h.gas_exponent = u.between(1.0001, 1.67);
    h.cavitation = u.next() < 0.2;
    h.chamber_volume = swept * u.log_between(1.2, 30.0);
    let b = &mut s.bistable;
    b.spring_stiffness = u.log_between(1e3, 5e4);
    b.half_span = u.between(0.015, 0.05);
    b.apex_rise = u.between(0.005, 0.02);
    b.offset = b.apex_rise * u.between(0.0, 0.5);
    s.solver.rtol = u.log_between(1e-9, 1e-3);
    s.solver.atol = s.solver.rtol * 1e-3;
    s.energy.ledger = u.next() < 0.8;
    let c = corners;
    let corner = u.next();
    if corner < c.compressible {
        s.hydraulic.bulk_modulus = u.log_between(1e8, 2e9);
        s.t_end = u.between(0.002, 0.01);
    } else if corner < c.compressible + c.fixed_step {
        let method = if u.next() < 0.5 { "rk4" } else { "euler" };
        s.set_from_str("solver.method", method).expect("a method");
        s.solver.fixed_step = u.log_between(1e-6, 1e-3);
    } else if corner < c.compressible + c.fixed_step + c.step_limit {
        s.solver.max_steps = u.log_between(1.0, 1e3) as u64;
    } else if corner < c.compressible + c.fixed_step + c.step_limit + c.stiffness_stop {
        s.set_from_str("solver.stiffness", "stop")
            .expect("an action");
    }
    s
}
