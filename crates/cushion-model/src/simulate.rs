//! One run: scene in, summary (and optionally trajectory and event log) out.
//!
//! The scene is validated, assembled into a [`Model`] holding only its parts, solved with
//! `cushion-ode` over a state of the size the scene needs (the integrator is generic over the
//! state size `N`; the run picks `N` from the scene's [`Layout`](crate::model::Layout) at run time), and reduced to a
//! [`Summary`].
//!
//! - Robot impulse `int F_r dt` is exact from momentum: `F_r = -(m_t a_t + F_c)` and
//!   `m_p a_p = F_c` give `int F_r dt = -(m_t dv_t + m_p dv_p)` (rigid: `dv_r` for `dv_t`); with
//!   plane friction `int F_c dt` is a quadrature state instead.
//! - Early end: once the robot stands, the tool has settled (stuck by dry friction, or its
//!   relative speed below `100 atol` m/s and its acceleration below `1000 atol` m/s^2), and the
//!   object is out of contact and either free and not slower than the tool or stuck on the
//!   plane, nothing can change any more: the run stops and the final values at `t_end` are
//!   extrapolated exactly (object at constant speed, everything else at rest). The same holds
//!   while the robot cruises on with no brake before `t_end` (its sensor never switched, or the
//!   dead time ends after the run), the object free and not slower than the tool, and the tool
//!   stuck short of the sensor or at rest on its stop (`resting.rs`: a tool pressed onto its stop
//!   is overdamped there, and the explicit solution keeps a wobble of the tolerance's size that
//!   the speed test above would never let pass); the tool then rides with the robot. Failing
//!   that, the run may end once only the tool's small ringing on its stop is left, written in
//!   closed form (`ringing_tail.rs`).

use crate::config::{Module, Scene};
use crate::model::{to_point, Model};
use crate::physics;
use crate::recorder::{Observed, Recorder};
use crate::summary::{RunStatus, SolverStats, Summary};
use crate::trajectory::{EventLogEntry, Trajectory};
use cushion_ode::{Output, SolverOptions, State, Stats, Status, Tolerance};

/// What to record besides the summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunOptions {
    /// Record the trajectory: every accepted step's end and every event, plus uniform samples
    /// every `sample_interval` seconds from the dense output when that is set.
    pub trajectory: bool,
    pub sample_interval: Option<f64>,
}

impl RunOptions {
    /// A recorded run as users ask for one (`cushion simulate --csv`, Python's `simulate`):
    /// samples every `sample_interval` seconds, by default `t_end / 2000`; `0` records the
    /// solver's steps and events only. A negative or non-finite interval is refused with what
    /// is allowed (the caller names the interval as its user typed it).
    pub fn recording(scene: &Scene, sample_interval: Option<f64>) -> Result<RunOptions, String> {
        let sample_interval = match sample_interval {
            Some(dt) if !dt.is_finite() || dt < 0.0 => {
                return Err(
                    "expected a finite number of seconds >= 0 (0: steps and events only)".into(),
                )
            }
            Some(0.0) => None,
            Some(dt) => Some(dt),
            None => Some(scene.t_end / 2000.0).filter(|dt| *dt > 0.0),
        };
        Ok(RunOptions {
            trajectory: true,
            sample_interval,
        })
    }
}

/// What one run yields.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    pub summary: Summary,
    /// `Some` when `RunOptions::trajectory` was set and the scene was valid.
    pub trajectory: Option<Trajectory>,
    /// Every event in time order (always recorded; it is short).
    pub events: Vec<EventLogEntry>,
}

pub use crate::model::MAX_STATES;

struct Outcome {
    status: Status,
    message: String,
    t: f64,
    y: Vec<f64>,
    stats: Stats,
}

fn run<const N: usize>(system: &mut Observed, opts: &SolverOptions, t_end: f64) -> Outcome {
    let y0 = State::<N>::from_column_slice(&system.model.y0);
    let sol = cushion_ode::solve(system, 0.0, y0, t_end, opts);
    Outcome {
        status: sol.status,
        message: sol.message,
        t: sol.t,
        y: sol.y.as_slice().to_vec(),
        stats: sol.stats,
    }
}

/// The integrator settings of a scene.
pub fn solver_options(scene: &Scene) -> SolverOptions {
    let mut time_stops = Vec::new();
    if scene.robot.start == crate::config::RobotStart::Rest {
        time_stops.push(scene.robot.approach_speed / scene.robot.acceleration);
    }
    SolverOptions {
        method: scene.solver.method,
        rtol: Tolerance::Scalar(scene.solver.rtol),
        atol: Tolerance::Scalar(scene.solver.atol),
        fixed_step: scene.solver.fixed_step,
        max_steps: scene.solver.max_steps,
        stiffness: scene.solver.stiffness,
        time_stops,
        output: Output::None,
        ..SolverOptions::default()
    }
}

/// Run one scene. Never panics: an invalid scene gives status `invalid` with the validation
/// message; a solver failure gives its status and message.
pub fn simulate(scene: &Scene, opts: &RunOptions) -> RunResult {
    simulate_with_ledger(scene, opts).0
}

/// The terms of the energy ledger at the end of a run (SPEC section 5), J.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyLedger {
    /// Work done by the robot on the module, `int -F_r v_r dt`.
    pub work: f64,
    /// Change of the kinetic energy of tool and object.
    pub kinetic: f64,
    /// Change of the gas energy.
    pub gas: f64,
    /// Change of the elastic energy of contacts, stops and the bistable springs.
    pub elastic: f64,
    /// Dissipated: orifice, tool friction, contact damping, plane friction.
    pub dissipated: f64,
    /// `|work - (kinetic + gas + elastic + dissipated)|` over the largest term of the balance
    /// `W + E(0) = E(t) + D`: the work, each dissipation, each energy change, and the kinetic,
    /// gas and elastic energies held at the start and at the end.
    pub residual: f64,
}

/// [`simulate`], and the energy ledger's terms (`None` with the ledger off or bad input).
pub fn simulate_with_ledger(scene: &Scene, opts: &RunOptions) -> (RunResult, Option<EnergyLedger>) {
    if let Err(e) = scene.validate() {
        let r = RunResult {
            summary: Summary::invalid(e.to_string()),
            trajectory: None,
            events: Vec::new(),
        };
        return (r, None);
    }
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| simulate_valid(scene, opts))) {
        Ok(r) => r,
        Err(_) => {
            let r = RunResult {
                summary: Summary::invalid(
                    "internal error: the model panicked (please report this scene)",
                ),
                trajectory: None,
                events: Vec::new(),
            };
            (r, None)
        }
    }
}

/// Energy ledger of a finished run: `(residual, [W, dKE, dE_gas, dE_elastic, D_total])`.
pub(crate) fn energy_ledger(model: &Model, t: f64, y: &[f64]) -> Option<(f64, [f64; 5])> {
    let l = model.layout;
    let w = y[l.work?];
    let p = &model.p;
    let seg0 = *model.robot.segment_at(0.0);
    let seg1 = *model.robot.segment_at(t);
    let tool_v = |t: f64, y: &[f64], seg: &physics::Segment| match l.tool {
        Some(i) => y[i + 1],
        None => seg.at(t).1,
    };
    let tool_x = |t: f64, y: &[f64], seg: &physics::Segment| match l.tool {
        Some(i) => y[i],
        None => seg.at(t).0,
    };
    let y0 = &model.y0;
    let ke = |t: f64, y: &[f64], seg: &physics::Segment| {
        let vt = tool_v(t, y, seg);
        let mut k = 0.5 * p.m_t * vt * vt;
        if let Some(j) = l.object {
            k += 0.5 * p.m_p * y[j + 1] * y[j + 1];
        }
        k
    };
    let stored = |t: f64, y: &[f64], seg: &physics::Segment| -> (f64, f64) {
        let (x_r, _, _) = seg.at(t);
        let x_t = tool_x(t, y, seg);
        let s = x_r - x_t;
        let mut gas = 0.0;
        let mut el = 0.0;
        match p.module {
            Module::Hydraulic => {
                gas = match l.liquid {
                    Some(q) => physics::gas_energy(p.p10, p.v_g0, 1.0, p.kappa, y[q + 1]),
                    None => physics::gas_energy(p.p10, p.v_g0, p.a_p, p.kappa, s),
                };
                if let Some(k) = l.e_liquid {
                    el += y[k];
                }
            }
            Module::Bistable => el += physics::bistable_energy(p.k_b, p.w, p.h, s + p.e),
            Module::Rigid => {}
        }
        if l.tool.is_some() {
            el += physics::hunt_crossley_energy(p.k_e, -s)
                + physics::hunt_crossley_energy(p.k_e, s - p.stroke);
        }
        if let Some(j) = l.object {
            el += physics::hunt_crossley_energy(p.k_c, x_t - y[j]);
        }
        (gas, el)
    };
    let (ke1, ke0) = (ke(t, y, &seg1), ke(0.0, y0, &seg0));
    let d_ke = ke1 - ke0;
    let (g1, e1) = stored(t, y, &seg1);
    let (g0, e0) = stored(0.0, y0, &seg0);
    let (d_gas, d_el) = (g1 - g0, e1 - e0);
    let ds = [l.d_orifice, l.d_friction, l.d_contact, l.d_plane];
    let d_total: f64 = ds.iter().flatten().map(|&k| y[k]).sum();
    // The largest term of the balance `W + E(0) = E(t) + D` (`E` = kinetic + gas + elastic),
    // the energies held at either end included: in a scene where nothing happens (no impact,
    // the tool riding along at rest) the work and the changes are all of rounding size, and
    // their mismatch over the largest of them alone would be noise over noise (~1).
    let scale = [w, d_ke, d_gas, d_el, ke0, ke1, g0, g1, e0, e1]
        .into_iter()
        .chain(ds.iter().flatten().map(|&k| y[k]))
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let mismatch = w - (d_ke + d_gas + d_el + d_total);
    let residual = if scale > 0.0 {
        mismatch.abs() / scale
    } else {
        mismatch.abs()
    };
    Some((residual, [w, d_ke, d_gas, d_el, d_total]))
}

fn simulate_valid(scene: &Scene, opts: &RunOptions) -> (RunResult, Option<EnergyLedger>) {
    let model = Model::new(scene);
    let recorder = opts
        .trajectory
        .then(|| Recorder::new(&model, opts.sample_interval));
    let mut system = Observed { model, recorder };
    let sopts = solver_options(scene);
    let t_end = scene.t_end;
    let out = match system.model.layout.n.max(1) {
        1 => run::<1>(&mut system, &sopts, t_end),
        2 => run::<2>(&mut system, &sopts, t_end),
        3 => run::<3>(&mut system, &sopts, t_end),
        4 => run::<4>(&mut system, &sopts, t_end),
        5 => run::<5>(&mut system, &sopts, t_end),
        6 => run::<6>(&mut system, &sopts, t_end),
        7 => run::<7>(&mut system, &sopts, t_end),
        8 => run::<8>(&mut system, &sopts, t_end),
        9 => run::<9>(&mut system, &sopts, t_end),
        10 => run::<10>(&mut system, &sopts, t_end),
        11 => run::<11>(&mut system, &sopts, t_end),
        12 => run::<12>(&mut system, &sopts, t_end),
        13 => run::<13>(&mut system, &sopts, t_end),
        n => {
            let r = RunResult {
                summary: Summary::invalid(format!(
                    "internal error: {n} states (at most {MAX_STATES})"
                )),
                trajectory: None,
                events: Vec::new(),
            };
            return (r, None);
        }
    };
    let Observed {
        mut model,
        recorder,
    } = system;
    model.refine_peaks();
    let status = match out.status {
        Status::Success | Status::StoppedByEvent => RunStatus::Ok,
        Status::MaxSteps => RunStatus::MaxSteps,
        Status::StepTooSmall => RunStatus::StepTooSmall,
        Status::NonFinite => RunStatus::NonFinite,
        Status::Stiff => RunStatus::Stiff,
        Status::InvalidInput => RunStatus::Invalid,
    };
    // The stiffness warning is in `stats.stiff`; the message stays empty for a run that is ok.
    let message = if status == RunStatus::Ok {
        String::new()
    } else {
        out.message.clone()
    };
    // Final state; extrapolated to t_end after an early end (exactly, or by the ringing tail's
    // closed form).
    let mut y = out.y.clone();
    let mut t = out.t;
    if let Some(te) = model.early_end {
        // the robot's kinks inside a ringing tail: its profile gets them, the log names them
        let kinks = model
            .ringing_tail
            .as_ref()
            .map_or((None, None), |r| (r.brake, r.stop));
        if let Some(tb) = kinks.0 {
            model.robot.brake(tb);
            model.log_extrapolated("brake", te, &out.y, tb);
        }
        if let Some(ts) = kinks.1 {
            model.robot.on_time(ts);
            model.log_extrapolated("robot_stopped", te, &out.y, ts);
        }
        y = model.extrapolated(te, &out.y, t_end);
        if model.ringing_tail.is_some() {
            close_ledger_after_tail(&model, te, &out.y, t_end, &mut y);
        }
        t = t_end;
        let pt = model.point_at(te, &out.y);
        model.log.push(EventLogEntry {
            t: te,
            name: "early_end".into(),
            point: pt,
        });
    }
    let l = model.layout;
    let p = model.p.clone();
    let seg_end = *model.robot.segment_at(t);
    let e_end = model.eval(t, &y, &seg_end, &model.regime);

    let (object_final_velocity, object_final_momentum, object_travel) = match l.object {
        Some(j) => (
            Some(y[j + 1]),
            Some(p.m_p * y[j + 1]),
            Some(y[j] - model.y0[j]),
        ),
        None => (None, None, None),
    };
    // Robot impulse from momentum.
    let seg0 = *model.robot.segment_at(0.0);
    let v_t0 = match l.tool {
        Some(i) => model.y0[i + 1],
        None => seg0.at(0.0).1,
    };
    let mut impulse = -p.m_t * (e_end.v_t - v_t0);
    if let Some(k) = l.contact_impulse {
        impulse -= y[k];
    } else if let Some(j) = l.object {
        impulse -= p.m_p * (y[j + 1] - model.y0[j + 1]);
    }
    let ledger = energy_ledger(&model, t, &y).map(
        |(residual, [work, kinetic, gas, elastic, dissipated])| EnergyLedger {
            work,
            kinetic,
            gas,
            elastic,
            dissipated,
            residual,
        },
    );
    let energy_residual = ledger.map(|l| l.residual);
    let max_gas_pressure = match p.module {
        Module::Hydraulic if l.liquid.is_some() => Some(model.metrics.max_p1),
        Module::Hydraulic => Some(physics::gas_pressure(
            p.p10,
            p.v_g0,
            p.a_p,
            p.kappa,
            model.metrics.max_stroke,
        )),
        _ => None,
    };
    let t_brake = model.robot.t_brake;
    let m = &model.metrics;
    let summary = Summary {
        status,
        message,
        t_detect: m.t_detect,
        t_brake,
        peak_robot_force: m.peak_fr,
        t_peak_robot_force: m.t_peak_fr,
        robot_impulse: impulse,
        peak_contact_force: m.peak_fc,
        object_impacts: m.object_impacts,
        forward_stop_impacts: m.fwd_impacts,
        back_stop_impacts: m.back_impacts,
        object_final_velocity,
        object_final_momentum,
        object_travel,
        max_stroke: if l.tool.is_some() { m.max_stroke } else { 0.0 },
        back_stop_hit: m.back_hit,
        max_gas_pressure,
        energy_residual,
        stats: SolverStats {
            steps: out.stats.steps,
            rejected: out.stats.rejected,
            rhs_evals: out.stats.rhs_evals,
            events: out.stats.events,
            stiff: out.stats.stiff,
            jacobians: out.stats.jacobian_evals,
            lu_decompositions: out.stats.lu_decompositions,
            method_switches: out.stats.method_switches,
        },
    };
    // After an early end, the uniform samples up to t_end come from the extrapolation; without
    // uniform samples, a ringing tail is drawn with 16 points per period.
    let mut tail = Vec::new();
    if let (Some(te), Some(rec)) = (model.early_end, &recorder) {
        let spacing = match (rec.sample_interval, &model.ringing_tail) {
            (Some(dt), _) => Some((dt, (rec.next_sample / dt).round() as u64)),
            (None, Some(r)) => {
                let w0 = r.pieces.last().map_or(1.0, |p| p.ring.w0);
                let dt = 2.0 * std::f64::consts::PI / w0 / 16.0;
                Some((dt, (te / dt).floor() as u64 + 1))
            }
            (None, None) => None,
        };
        if let Some((dt, mut k)) = spacing {
            loop {
                let ts = k as f64 * dt;
                if ts >= t_end {
                    break;
                }
                if ts > te {
                    tail.push(model.point_at(ts, &model.extrapolated(te, &out.y, ts)));
                }
                k += 1;
            }
        }
    }
    let trajectory = recorder.map(|rec| {
        let mut pts = rec.points;
        pts.extend(tail);
        if model.early_end.is_some() {
            pts.push(to_point(t, &e_end));
        }
        pts.sort_by(|a, b| a.t.total_cmp(&b.t));
        // Keep both sides of a jump (kinks of the robot profile); drop exact duplicates.
        pts.dedup_by(|b, a| {
            a.values()
                .iter()
                .zip(b.values().iter())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        });
        Trajectory { points: pts }
    });
    let mut events = std::mem::take(&mut model.log);
    events.sort_by(|a, b| a.t.total_cmp(&b.t));
    let result = RunResult {
        summary,
        trajectory,
        events,
    };
    (result, ledger)
}

/// After a ringing tail: add the robot's work during it (exact) and close the ledger with the
/// dissipation, so that the residual is that of the integrated part.
fn close_ledger_after_tail(model: &Model, te: f64, y_te: &[f64], t_end: f64, y: &mut [f64]) {
    let l = model.layout;
    let Some(k_work) = l.work else {
        return;
    };
    y[k_work] += model.ringing_tail_work(t_end);
    let (Some((_, a)), Some((_, b))) = (
        energy_ledger(model, te, y_te),
        energy_ledger(model, t_end, y),
    ) else {
        return;
    };
    let stored = |v: &[f64; 5]| v[1] + v[2] + v[3];
    let dissipated = (b[0] - a[0]) - (stored(&b) - stored(&a));
    if let Some(k) = [l.d_contact, l.d_friction, l.d_orifice]
        .into_iter()
        .flatten()
        .next()
    {
        y[k] += dissipated;
    }
}
