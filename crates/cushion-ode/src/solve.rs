//! The integration loop: plan a step, attempt it, guard it, scan it for events, keep it. It
//! orchestrates; each of those ideas lives in its own file (`step_plan.rs`; `stepper.rs` and
//! `controller.rs`; `step_guard.rs`; `events.rs`; `record.rs`).

use crate::auto::AutoSwitch;
use crate::dense::DenseOutput;
use crate::dop853::Dop853;
use crate::dopri5::Dopri5;
use crate::events::EventScan;
use crate::norm::Weights;
use crate::observer::Observer;
use crate::options::{Method, SolverOptions};
use crate::record::Recorder;
use crate::rodas::Rodas;
use crate::solution::{Solution, Stats, Status};
use crate::step_guard::{Stability, StepGuard};
use crate::step_plan::{Planned, StepPlan, Stepping};
use crate::stepper::{Attempt, ExplicitRk, Stepper};
use crate::stiffness::StiffnessDetector;
use crate::system::{Control, EventAction, OdeSystem, Step};
use crate::tableau::{CLASSICAL_RK4, EXPLICIT_EULER};
use crate::State;

mod attempt;
mod restart;

use attempt::Tried;

/// Integrate `sys` from `(t0, y0)` to `t_end` with the settings `opts`. Never panics on bad
/// numbers: it returns a [`Solution`] whose status says how it ended.
pub fn solve<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t0: f64,
    y0: State<N>,
    t_end: f64,
    opts: &SolverOptions,
) -> Solution<N> {
    solve_observed(sys, &mut (), t0, y0, t_end, opts)
}

/// [`solve`] with an observer beside the problem (`observer.rs`): it sees every accepted step,
/// the events and time stops the problem handled, and every change of method.
pub fn solve_observed<S: OdeSystem<N>, O: Observer<S, N>, const N: usize>(
    sys: &mut S,
    observer: &mut O,
    t0: f64,
    y0: State<N>,
    t_end: f64,
    opts: &SolverOptions,
) -> Solution<N> {
    let problem = (sys, observer, t0, y0, t_end, opts);
    match opts.method {
        // The hot path: DOPRI5 with constant coefficients (same numbers as its tableau).
        Method::Dp5 => run(problem, &mut Dopri5::<N>::new()),
        Method::Dop853 => run(problem, &mut Dop853::<N>::new()),
        Method::Rodas => run(problem, &mut Rodas::<N>::new()),
        Method::Auto => run(problem, &mut AutoSwitch::<N>::new(opts)),
        Method::Rk4 => run(problem, &mut ExplicitRk::<N>::new(&CLASSICAL_RK4)),
        Method::Euler => run(problem, &mut ExplicitRk::<N>::new(&EXPLICIT_EULER)),
    }
}

/// The problem, its observer, the start, the end and the settings of one solve.
type Problem<'a, S, O, const N: usize> =
    (&'a mut S, &'a mut O, f64, State<N>, f64, &'a SolverOptions);

/// [`solve_observed`] with the method's stepper.
fn run<S: OdeSystem<N>, O: Observer<S, N>, M: Stepper<N>, const N: usize>(
    (sys, observer, t0, y0, t_end, opts): Problem<'_, S, O, N>,
    stepper: &mut M,
) -> Solution<N> {
    let mut run = Integration::new(sys, observer, t0, y0, t_end, opts);
    let (status, message) = run.integrate(stepper);
    stepper.add_counts(&mut run.stats);
    Solution {
        status,
        message,
        t: run.t,
        y: run.y,
        ts: run.out.ts,
        ys: run.out.ys,
        events: run.events.log,
        stats: run.stats,
    }
}

/// How a run ended, and a message (empty when all went well).
type End = (Status, String);

/// Where the run stands since the last restart (an event or a time stop that changed the
/// regime): how the next accepted step's error is judged.
#[derive(Clone, Copy)]
struct SinceRestart {
    /// No step accepted since the restart. Not at the run's start: a smooth problem starts
    /// smooth. A rejected first step is retried as after a discontinuity
    /// (`controller::retry_after_discontinuity`).
    fresh: bool,
    /// No step accepted since a restart at an event whose function is, in the new regime, a
    /// kink of `f` ([`OdeSystem::kinked_at_event`]): the first step starts where a force sets
    /// in like `delta^1.5` (a contact's onset). Only for a method that lands on kinks.
    on_kink: bool,
}

/// An accepted step that the guard and the event scan let stand, from `(t, y)` of size `h`.
struct Scanned<'a, const N: usize> {
    t: f64,
    y: &'a State<N>,
    h: f64,
    /// Where the step ends (`Planned::end`).
    t1: f64,
    /// The size the controller proposes next, and the scaled error the step was accepted with.
    h_new: f64,
    err_norm: Option<f64>,
    attempt: &'a Attempt<N>,
    dense: &'a DenseOutput<N>,
    dense_stable: bool,
    /// Where the scan ended the step (its end, unless a handler cut it), the state there
    /// after the handlers, and the strongest action they took.
    t_cut: f64,
    y_cut: &'a State<N>,
    action: EventAction,
}

struct Integration<'a, S, O, const N: usize> {
    sys: &'a mut S,
    observer: &'a mut O,
    opts: &'a SolverOptions,
    t_end: f64,
    t: f64,
    y: State<N>,
    /// `f(t, y)`: the next step's first slope.
    f: State<N>,
    stats: Stats,
    weights: Weights<N>,
    events: EventScan<N>,
    out: Recorder<N>,
    since_restart: SinceRestart,
    plan: StepPlan,
}

impl<'a, S: OdeSystem<N>, O: Observer<S, N>, const N: usize> Integration<'a, S, O, N> {
    fn new(
        sys: &'a mut S,
        observer: &'a mut O,
        t0: f64,
        y0: State<N>,
        t_end: f64,
        opts: &'a SolverOptions,
    ) -> Self {
        let n_events = sys.event_count();
        Integration {
            sys,
            observer,
            opts,
            t_end,
            t: t0,
            y: y0,
            f: State::<N>::zeros(),
            stats: Stats::default(),
            weights: Weights::of(opts),
            events: EventScan::new(n_events, opts, t_end - t0),
            out: Recorder::new(),
            since_restart: SinceRestart {
                fresh: false,
                on_kink: false,
            },
            plan: StepPlan::new(t0, t_end, opts),
        }
    }

    #[inline]
    fn rhs(&mut self, t: f64, y: &State<N>) -> State<N> {
        self.stats.rhs_evals += 1;
        self.sys.rhs(t, y)
    }

    /// The loop itself, in the shape of SciPy's `solve_ivp`: plan a step, attempt it, guard
    /// it, scan it for events, keep it.
    fn integrate<M: Stepper<N>>(&mut self, stepper: &mut M) -> End {
        if let Some(end) = self.start(stepper) {
            return end;
        }
        let (stepping, stability) = (Stepping::of(stepper), Stability::of(stepper));
        let adaptive = stepping.adaptive;
        let mut controller = stepper.controller(self.opts);
        let mut stiffness = StiffnessDetector::with_threshold(stepper.stiffness_threshold());
        let mut h = self.first_step(stepper);
        let mut ctl = Control::new();
        let mut guard = StepGuard::new();
        // Every attempt is written here in place (`Stepper::step_into`).
        let mut attempt = Attempt::<N>::empty();
        loop {
            if self.stats.steps + self.stats.rejected >= self.opts.max_steps {
                return self.step_limit(&stiffness);
            }
            let (crossing, forecast) = (self.events.next_crossing(), guard.allows_forecast());
            let step = match self.plan.next(self.t, h, crossing, forecast, stepping) {
                Ok(step) => step,
                Err(h) => {
                    let msg = format!("step size too small: h = {h:e} at t = {}", self.t);
                    return (Status::StepTooSmall, msg);
                }
            };
            h = step.h;
            let (t, y, f0, since_restart) = (self.t, self.y, self.f, self.since_restart);
            let (h_new, err_norm) =
                match self.attempt(stepper, &mut controller, adaptive, h, &mut attempt) {
                    Tried::Accepted(h_new, err_norm) => (h_new, err_norm),
                    Tried::Retry(h_retry) => {
                        h = h_retry;
                        continue;
                    }
                    Tried::End(status, msg) => return (status, msg),
                };
            let h_lambda = self.h_lambda(stepper, &stability, h, &attempt);
            if let Some(h_again) = guard.jumped(&stability, adaptive, h, h_lambda) {
                self.take_back(since_restart, h);
                h = h_again;
                continue;
            }
            let h_new = self.plan.accepted(&step, h_new);
            let dense_stable = crate::stiffness::dense_stable(h_lambda, stability.dense_bound);
            if let Some(end) = self.observe_stiffness(&mut stiffness, t, h, h_lambda, &attempt) {
                return end;
            }
            let t1 = step.end(t);
            let dense = stepper.dense(t, t1 - t, &y, &f0, &attempt);
            // Events inside (t, t1]. On a dense output that is not stable, any crossing asks
            // for the step again, once, short enough for it to be stable (`step_guard.rs`).
            let unstable_at = guard.unstable_at(adaptive, h_lambda, dense_stable);
            let events_before = self.stats.events;
            let (t_cut, y_cut, action) = self.events.scan(
                &mut *self.sys,
                &dense,
                (t, t1),
                &attempt.y1,
                &mut ctl,
                &mut self.stats,
                guard.redoes_kinks(stepping.lands_on_kinks),
                unstable_at.is_some(),
            );
            if self.stats.events != events_before {
                self.observer.after_events(&*self.sys);
            }
            if let Some(t_cross) = self.events.take_redo() {
                self.take_back(since_restart, h);
                h = guard.retake(&stability, t, h, t_cross, unstable_at);
                continue;
            }
            let h_new = guard.kept(&stability, h, step.h_ctrl, h_lambda, h_new);
            let scanned = Scanned {
                t,
                y: &y,
                h,
                t1,
                h_new,
                err_norm,
                attempt: &attempt,
                dense: &dense,
                dense_stable,
                t_cut,
                y_cut: &y_cut,
                action,
            };
            h = match self.keep(stepper, &mut controller, &mut ctl, &step, scanned) {
                Ok(h_next) => h_next,
                Err(end) => return end,
            };
        }
    }

    /// The run's end at the step limit, with what the stiffness test saw up to there.
    #[cold]
    fn step_limit(&self, stiffness: &StiffnessDetector) -> End {
        let mut msg = format!(
            "step limit {} reached at t = {}",
            self.opts.max_steps, self.t
        );
        if let Some(n) = stiffness.held_near_limit() {
            // `stiffness::PATIENT_STEPS`; `cushion-model/tests/model/statuses.rs`
            msg.push_str(&format!(
                "; {n} steps in a row up to here were held by the method's stability, \
                 not its accuracy (h*lambda above {:.2} on each): the problem is stiff \
                 there, and an implicit method (rodas, or auto) takes it in far fewer \
                 steps",
                stiffness.near_limit()
            ));
        }
        (Status::MaxSteps, msg)
    }

    /// Keep the step `s` (planned as `step`): record it, tell the system, forecast the next
    /// kink, take a change of method, then start the next step: after an event that cut the
    /// step, at a time stop, or from the step's end. The size to plan the next step from, or
    /// the run's end.
    #[inline(always)]
    fn keep<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        controller: &mut M::Controller,
        ctl: &mut Control,
        step: &Planned,
        s: Scanned<'_, N>,
    ) -> Result<f64, End> {
        let (t, dense) = (s.t, s.dense);
        let cut = s.action != EventAction::Continue;
        let (t_new, y_new) = if cut {
            (s.t_cut, *s.y_cut)
        } else {
            (s.t1, s.attempt.y1)
        };
        // Only the part of the step the run keeps teaches a restart its first step.
        let kept = if cut { s.t_cut - t } else { s.h };
        self.plan.kept(kept, s.err_norm, stepper.order());
        // The step as it ended, before any handler changed the state.
        let y_end = if cut { dense.eval(t_new) } else { y_new };
        self.out
            .record(&self.opts.output, t, Some(dense), t_new, &y_end);
        let (y0, dense_stable) = (s.y, s.dense_stable);
        let step_seen = Step {
            t0: t,
            t1: t_new,
            y0,
            y1: &y_end,
            dense,
            dense_stable,
        };
        self.observer.on_step(&*self.sys, &step_seen);
        self.sys.on_step(&step_seen, ctl);
        self.observer.after_step(&*self.sys, &step_seen, ctl);
        if stepper.lands_on_kinks() && !cut {
            self.plan.after_step(&*self.sys, dense, (t, t_new), &y_new);
        }
        let mut h_new = s.h_new;
        if let Some(switch) = stepper.take_switch() {
            if switch.to_stiff && !self.stats.stiff {
                self.stats.stiff = true;
                self.stats.stiff_since = Some(switch.since);
            }
            self.sys.on_switch(t_new, &y_new, switch.to);
            self.observer.after_switch(&*self.sys, switch.to);
            *controller = stepper.controller(self.opts);
            self.plan.forget_restart_steps();
            h_new = h_new.min(switch.h_max);
        }
        self.t = t_new;
        self.y = y_new;
        self.plan.add_stops(t_new, ctl);
        if s.action == EventAction::Stop || ctl.stop_requested {
            return Err((Status::StoppedByEvent, String::new()));
        }
        if cut {
            return self.restart_after_event(stepper, controller, t_new, &y_new, s.h, h_new);
        }
        if step.landing {
            if self.plan.at_end(t_new) {
                return Err((Status::Success, String::new()));
            }
            return self
                .take_time_stop(stepper, t_new, y_new, ctl)
                .map(|()| h_new);
        }
        // The next step's first slope: the method's last stage (FSAL), or evaluated here.
        self.take_next_slope(s.attempt.f1, t_new, &y_new)
            .map(|()| h_new)
    }
}
