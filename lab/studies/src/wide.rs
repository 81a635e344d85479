//! Random scenes far outside the paper's: every key of docs/scene-keys.md over a wide range.
//! Shared by the `wide_scenes`, `wide_accuracy` and `wide_trajectories` binaries (many scenes,
//! a report) and `lab/studies/tests/wide_scenes.rs`.

use crate::Uniform;
use cushion_model::config::RobotStart;
use cushion_model::{simulate, Module, RunOptions, RunResult, Scene, Summary, TrajectoryPoint};

/// The leading `N SEED` arguments of the wide-scene binaries (defaults 1000 and one fixed seed),
/// so that `wide_scenes` and `wide_accuracy` draw the same scenes from the same arguments.
pub fn count_and_seed(args: &mut impl Iterator<Item = String>) -> (usize, u64) {
    let n = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let seed = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(0x5DEECE66D);
    (n, seed)
}

/// The `--method M` flag of the wide-scene binaries, taken out of `args`: the adaptive method
/// every drawn scene is run with (the draw's own, `dp5`, without it; a corner's fixed-step
/// method is kept).
pub fn method_flag(args: &mut Vec<String>) -> Option<String> {
    let at = args.iter().position(|a| a == "--method")?;
    args.remove(at);
    (at < args.len()).then(|| args.remove(at))
}

/// `s` under the adaptive `method` of [`method_flag`], if one was given and `s` is adaptive.
pub fn with_method(mut s: Scene, method: Option<&str>) -> Scene {
    if let Some(m) = method.filter(|_| s.solver.method.is_adaptive()) {
        s.set_from_str("solver.method", m)
            .unwrap_or_else(|e| panic!("--method {m}: {e}"));
    }
    s
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

/// How a recorded run's trajectory (`run_recorded`) disagrees in kind with its summary: it does
/// not end at `t_end`, its time runs backwards, or its last object speed is not the summary's
/// final one. Empty when it agrees.
pub fn trajectory_mismatches(s: &Scene, r: &RunResult) -> Vec<String> {
    let mut found = Vec::new();
    let pts = &r.trajectory.as_ref().expect("recorded").points;
    let last = pts.last().expect("a point");
    if last.t != s.t_end {
        found.push(format!("ends at {} not t_end {}", last.t, s.t_end));
    }
    if pts.windows(2).any(|w| w[1].t < w[0].t) {
        found.push("time runs backwards".to_string());
    }
    if let Some(v) = r.summary.object_final_velocity {
        if last.v_p != v {
            found.push(format!("last v_p {} vs summary {v}", last.v_p));
        }
    }
    found
}

/// Each peak of a recorded run's summary against its trajectory: `(name, reported peak, largest
/// sample, scale)` for `|F_r|`, `F_c` (scale: the peak or 1 mN), the stroke (the larger of the
/// stroke length and the largest stroke) and the gas pressure (its peak; without gas the peak
/// is infinite). The peaks are searched on the same dense output the samples come from, so a
/// sample above a peak is a peak the search missed.
pub fn peaks_and_samples(s: &Scene, r: &RunResult) -> [(&'static str, f64, f64, f64); 4] {
    let m = &r.summary;
    let pts = &r.trajectory.as_ref().expect("recorded").points;
    let top = |f: fn(&TrajectoryPoint) -> f64| {
        pts.iter()
            .map(f)
            .filter(|v| v.is_finite())
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let gas = m.max_gas_pressure.unwrap_or(f64::INFINITY);
    [
        (
            "|F_r|",
            m.peak_robot_force.abs(),
            top(|p| p.f_r.abs()),
            m.peak_robot_force.abs().max(1e-3),
        ),
        (
            "F_c",
            m.peak_contact_force,
            top(|p| p.f_c),
            m.peak_contact_force.max(1e-3),
        ),
        (
            "stroke",
            m.max_stroke,
            top(|p| p.s),
            s.stops.stroke.max(m.max_stroke.abs()),
        ),
        ("gas pressure", gas, top(|p| p.p1), gas),
    ]
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
    // The draw's own method is dp5 (not the engine's default, auto): `--method` runs it
    // under another, and the stiffness-stop corner needs an explicit method to stop.
    s.set_from_str("solver.method", "dp5").expect("a method");
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
