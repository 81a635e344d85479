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
//! - Early end (`early_end/`): once nothing a summary reports can change, the run stops and
//!   its final values at `t_end` come from its tail in closed form (`early_end/tail.rs`).

use crate::config::{Module, Scene};
use crate::early_end::{self, EarlyEnd, Tail};
use crate::ledger;
pub use crate::ledger::EnergyLedger;
use crate::model::{to_point, Eval, Model};
use crate::observe::recorder::Recorder;
use crate::observe::Observed;
use crate::peaks::{PeakSampler, Peaks};
use crate::physics;
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

fn run<const N: usize>(
    system: &mut Observed,
    opts: &SolverOptions,
    (t0, y0): (f64, &[f64]),
    t_end: f64,
) -> Outcome {
    let y0 = State::<N>::from_column_slice(y0);
    let (model, mut watchers) = system.split();
    let sol = cushion_ode::solve_observed(model, &mut watchers, t0, y0, t_end, opts);
    Outcome {
        status: sol.status,
        message: sol.message,
        t: sol.t,
        y: sol.y.as_slice().to_vec(),
        stats: sol.stats,
    }
}

/// One solve from `(t0, y0)` over a state of the layout's size (the integrator is generic over
/// it); `Err(n)` for a layout of more states than it is built for.
fn solve_from(
    system: &mut Observed,
    opts: &SolverOptions,
    from: (f64, &[f64]),
    t_end: f64,
) -> Result<Outcome, usize> {
    Ok(match system.model.layout.n.max(1) {
        1 => run::<1>(system, opts, from, t_end),
        2 => run::<2>(system, opts, from, t_end),
        3 => run::<3>(system, opts, from, t_end),
        4 => run::<4>(system, opts, from, t_end),
        5 => run::<5>(system, opts, from, t_end),
        6 => run::<6>(system, opts, from, t_end),
        7 => run::<7>(system, opts, from, t_end),
        8 => run::<8>(system, opts, from, t_end),
        9 => run::<9>(system, opts, from, t_end),
        10 => run::<10>(system, opts, from, t_end),
        n => return Err(n),
    })
}

/// After a ringing tail that ends at the robot's stop (`RingingTail::resume`): the tail played
/// to there (the robot's stop in its profile and the event log, the energy ledger's work and
/// losses over it added, the trajectory's points taken), and the time and state the run is
/// integrated on from. `None` when the run has ended.
fn resume_after_tail(system: &mut Observed, out: &Outcome, rtol: f64) -> Option<(f64, Vec<f64>)> {
    if out.status != Status::StoppedByEvent {
        return None;
    }
    let early_end = system.early_end.as_mut()?;
    let tail = early_end
        .tail
        .take_if(|tail| tail.resume_time().is_some())?;
    system.peaks.time_stop_ahead(&system.model);
    let (ts, mut y) = tail.resume(&mut system.model, &out.y)?;
    early_end::add_to_ledger(&system.model, &tail, &out.y, ts, rtol, &mut y);
    if let Some(recorder) = system.recorder.as_mut() {
        recorder.record_tail(&system.model, &tail, &out.y, ts);
        recorder.take_events(&system.model);
    }
    Some((ts, y))
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
        quadratures: crate::model::Layout::of(scene).quadratures(),
        ..SolverOptions::default()
    }
}

/// Run one scene. Never panics: an invalid scene gives status `invalid` with the validation
/// message; a solver failure gives its status and message.
pub fn simulate(scene: &Scene, opts: &RunOptions) -> RunResult {
    simulate_with_ledger(scene, opts).0
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

/// One run of a validated scene: the model with its observers, solved to the end (or the early
/// end and its tail), reduced to its summary, trajectory and event log.
fn simulate_valid(scene: &Scene, opts: &RunOptions) -> (RunResult, Option<EnergyLedger>) {
    let mut system = observed_model(scene, opts);
    let out = match solve_to_end(&mut system, scene) {
        Ok(out) => out,
        Err(n) => {
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
        mut peaks,
        early_end,
        recorder,
    } = system;
    peaks.finish(&model);
    // the half steps of the peak search (`peaks/top_step.rs`) count with the solver's
    // evaluations
    let mut out = out;
    out.stats.rhs_evals += peaks.halves_evals;
    let peaks = peaks.peaks;
    let tail = early_end.and_then(|e| e.tail);
    let (t, y) = final_state(&mut model, tail.as_ref(), &out, scene);
    let seg_end = *model.robot.segment_at(t);
    let e_end = model.eval(t, &y, &seg_end, &model.regime);
    let ledger = final_energy_ledger(&model, t, &y);
    let summary = summarise(&model, &peaks, &out, &y, &e_end, ledger);
    let trajectory = recorder.map(|rec| {
        rec.finish(
            &model,
            tail.as_ref(),
            &out.y,
            scene.t_end,
            to_point(t, &e_end),
        )
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

/// The model of a scene with the observers the run asks for: the peaks always, the early end
/// unless it is off, the trajectory when one is recorded.
fn observed_model(scene: &Scene, opts: &RunOptions) -> Observed {
    let model = Model::new(scene);
    let recorder = opts
        .trajectory
        .then(|| Recorder::new(&model, opts.sample_interval));
    Observed {
        peaks: PeakSampler::new(&model, scene.solver.rtol),
        early_end: scene.solver.early_end.then(|| EarlyEnd::new(scene)),
        model,
        recorder,
    }
}

/// Solve the scene to its end or its early end, the solver's counts summed over its solves:
/// a ringing tail that ends at the robot's stop is followed by a second solve from there.
/// `Err(n)` for a layout of more states than the integrator is built for.
fn solve_to_end(system: &mut Observed, scene: &Scene) -> Result<Outcome, usize> {
    let sopts = solver_options(scene);
    let mut start = (0.0, system.model.y0.clone());
    let mut stats = Stats::default();
    loop {
        let out = solve_from(system, &sopts, (start.0, &start.1), scene.t_end)?;
        stats += out.stats;
        match resume_after_tail(system, &out, scene.solver.rtol) {
            Some(resume) => start = resume,
            None => return Ok(Outcome { stats, ..out }),
        }
    }
}

/// The run's final time and state: where the solver stopped, or after an early end the
/// tail's at `t_end`, in closed form, with the ledger's work and losses over the tail added.
fn final_state(
    model: &mut Model,
    tail: Option<&Tail>,
    out: &Outcome,
    scene: &Scene,
) -> (f64, Vec<f64>) {
    match tail {
        Some(tail) => {
            let t_end = scene.t_end;
            let mut y = tail.play(model, &out.y, t_end);
            early_end::add_to_ledger(model, tail, &out.y, t_end, scene.solver.rtol, &mut y);
            (t_end, y)
        }
        None => (out.t, out.y.clone()),
    }
}

/// The energy ledger's terms at the run's end (`None` with the ledger off).
fn final_energy_ledger(model: &Model, t: f64, y: &[f64]) -> Option<EnergyLedger> {
    ledger::energy_ledger(model, t, y).map(
        |(residual, [work, kinetic, gas, elastic, dissipated])| EnergyLedger {
            work,
            kinetic,
            gas,
            elastic,
            dissipated,
            residual,
        },
    )
}

/// The summary of a finished run from its final state `y` (evaluated: `e_end`), its peaks,
/// the event handlers' metrics and the solver's outcome.
fn summarise(
    model: &Model,
    peaks: &Peaks,
    out: &Outcome,
    y: &[f64],
    e_end: &Eval,
    ledger: Option<EnergyLedger>,
) -> Summary {
    let (status, message) = run_status(out);
    let (object_final_velocity, object_final_momentum, object_travel) = object_at_end(model, y);
    let m = &model.metrics;
    Summary {
        status,
        message,
        t_detect: m.t_detect,
        t_brake: model.robot.t_brake,
        peak_robot_force: peaks.peak_fr,
        t_peak_robot_force: peaks.t_peak_fr,
        robot_impulse: robot_impulse(model, y, e_end),
        peak_contact_force: peaks.peak_fc,
        object_impacts: m.object_impacts,
        forward_stop_impacts: m.fwd_impacts,
        back_stop_impacts: m.back_impacts,
        object_final_velocity,
        object_final_momentum,
        object_travel,
        max_stroke: if model.layout.tool.is_some() {
            peaks.max_stroke
        } else {
            0.0
        },
        back_stop_hit: m.back_hit,
        max_gas_pressure: max_gas_pressure(model, peaks),
        energy_residual: ledger.map(|l| l.residual),
        stats: solver_stats(&out.stats),
    }
}

/// The run's status from the solver's, and its message (empty for a run that is ok: the
/// stiffness warning is in `stats.stiff`).
fn run_status(out: &Outcome) -> (RunStatus, String) {
    let status = match out.status {
        Status::Success | Status::StoppedByEvent => RunStatus::Ok,
        Status::MaxSteps => RunStatus::MaxSteps,
        Status::StepTooSmall => RunStatus::StepTooSmall,
        Status::NonFinite => RunStatus::NonFinite,
        Status::Stiff => RunStatus::Stiff,
        Status::InvalidInput => RunStatus::Invalid,
    };
    let message = if status == RunStatus::Ok {
        String::new()
    } else {
        out.message.clone()
    };
    (status, message)
}

/// The object's final velocity, momentum and travel (`None` without an object).
fn object_at_end(model: &Model, y: &[f64]) -> (Option<f64>, Option<f64>, Option<f64>) {
    match model.layout.object {
        Some(j) => (
            Some(y[j + 1]),
            Some(model.p.m_p * y[j + 1]),
            Some(y[j] - model.y0[j]),
        ),
        None => (None, None, None),
    }
}

/// The robot's impulse `int F_r dt`, exact from momentum: `-(m_t dv_t + m_p dv_p)`, or with
/// plane friction, which takes momentum from the object too, `-(m_t dv_t + int F_c dt)`.
fn robot_impulse(model: &Model, y: &[f64], e_end: &Eval) -> f64 {
    let (l, p) = (&model.layout, &model.p);
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
    impulse
}

/// The hydraulic module's largest gas pressure: sampled with a compressible liquid, else the
/// gas law's at the largest stroke (`None` for the other modules).
fn max_gas_pressure(model: &Model, peaks: &Peaks) -> Option<f64> {
    let p = &model.p;
    match p.module {
        Module::Hydraulic if model.layout.liquid.is_some() => Some(peaks.max_p1),
        Module::Hydraulic => Some(physics::gas_pressure(
            p.p10,
            p.v_g0,
            p.a_p,
            p.kappa,
            peaks.max_stroke,
        )),
        _ => None,
    }
}

/// The solver's counts as the summary reports them.
fn solver_stats(stats: &Stats) -> SolverStats {
    SolverStats {
        steps: stats.steps,
        rejected: stats.rejected,
        rhs_evals: stats.rhs_evals,
        events: stats.events,
        stiff: stats.stiff,
        jacobians: stats.jacobian_evals,
        lu_decompositions: stats.lu_decompositions,
        method_switches: stats.method_switches,
    }
}
