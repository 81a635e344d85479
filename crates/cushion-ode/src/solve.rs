//! The integration loop: plan a step, attempt it, guard it, scan it for events, keep it. It
//! orchestrates; each of those ideas lives in its own file (`step_plan.rs`; `stepper.rs` and
//! `controller.rs`; `step_guard.rs`; `events.rs`; `record.rs`).

use crate::auto::AutoSwitch;
use crate::controller::{initial_step, retry_after_discontinuity, Controller};
use crate::dense::DenseOutput;
use crate::dop853::Dop853;
use crate::dopri5::Dopri5;
use crate::events::EventScan;
use crate::kinks::MAX_KINKS;
use crate::norm::Weights;
use crate::options::{Method, SolverOptions, StiffnessAction};
use crate::record::Recorder;
use crate::rodas::Rodas;
use crate::solution::{Solution, Stats, Status};
use crate::step_guard::{Stability, StepGuard};
use crate::step_plan::{Planned, StepPlan};
use crate::stepper::{Attempt, Counted, ExplicitRk, StepFailure, Stepper};
use crate::stiffness::StiffnessDetector;
use crate::system::{Control, EventAction, OdeSystem, Step};
use crate::tableau::{CLASSICAL_RK4, EXPLICIT_EULER};
use crate::State;

/// Integrate `sys` from `(t0, y0)` to `t_end` with the settings `opts`. Never panics on bad
/// numbers: it returns a [`Solution`] whose status says how it ended.
pub fn solve<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t0: f64,
    y0: State<N>,
    t_end: f64,
    opts: &SolverOptions,
) -> Solution<N> {
    let problem = (sys, t0, y0, t_end, opts);
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

/// [`solve`] with the method's stepper.
fn run<S: OdeSystem<N>, M: Stepper<N>, const N: usize>(
    (sys, t0, y0, t_end, opts): (&mut S, f64, State<N>, f64, &SolverOptions),
    stepper: &mut M,
) -> Solution<N> {
    let mut run = Integration::new(sys, t0, y0, t_end, opts, stepper.is_adaptive());
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

/// Whether every number of an attempt is finite.
#[inline]
fn is_finite<const N: usize>(a: &Attempt<N>) -> bool {
    a.y1.iter().all(|v| v.is_finite())
        && a.f1.is_none_or(|f| f.iter().all(|v| v.is_finite()))
        && a.err.is_none_or(|e| e.iter().all(|v| v.is_finite()))
        && a.err_low.is_none_or(|e| e.iter().all(|v| v.is_finite()))
}

/// What became of one attempted step.
enum Tried {
    /// Accepted (and completed; the attempt is where the loop keeps it), with the step size
    /// the controller proposes next and the scaled error it was accepted with (`None`: not
    /// estimated), which the restart steps learn from once the loop keeps the step.
    Accepted(f64, Option<f64>),
    /// Rejected, or failed before its error estimate: try again with this size.
    Retry(f64),
    /// The run ends here.
    End(Status, String),
}

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
    /// The size the controller proposes next, and the scaled error the step was accepted with.
    h_new: f64,
    err_norm: Option<f64>,
    attempt: &'a Attempt<N>,
    dense: &'a DenseOutput<N>,
    dense_stable: bool,
    /// Where the scan ended the step (its end, unless a handler cut it), the state there
    /// after the handlers, and the strongest action they took.
    t_cut: f64,
    y_cut: State<N>,
    action: EventAction,
}

struct Integration<'a, S, const N: usize> {
    sys: &'a mut S,
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

impl<'a, S: OdeSystem<N>, const N: usize> Integration<'a, S, N> {
    fn new(
        sys: &'a mut S,
        t0: f64,
        y0: State<N>,
        t_end: f64,
        opts: &'a SolverOptions,
        adaptive: bool,
    ) -> Self {
        let n_events = sys.event_count();
        Integration {
            sys,
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
            plan: StepPlan::new(t0, t_end, opts, adaptive),
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
        let adaptive = stepper.is_adaptive();
        let stability = Stability::of(stepper);
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
            let lands = stepper.lands_on_kinks();
            let step = match self.plan.next(self.t, h, crossing, forecast, lands) {
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
            let (t_cut, y_cut, action) = self.events.scan(
                &mut *self.sys,
                &dense,
                (t, t1),
                &attempt.y1,
                &mut ctl,
                &mut self.stats,
                guard.redoes_kinks(stepper.lands_on_kinks()),
                unstable_at.is_some(),
            );
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
                h_new,
                err_norm,
                attempt: &attempt,
                dense: &dense,
                dense_stable,
                t_cut,
                y_cut,
                action,
            };
            h = match self.keep(stepper, &mut controller, &mut ctl, &step, scanned) {
                Ok(h_next) => h_next,
                Err(end) => return end,
            };
        }
    }

    /// The run's start: the settings checked, `f`, the output and the event and kink
    /// functions at `(t0, y0)`. The run's end if it ends there.
    fn start<M: Stepper<N>>(&mut self, stepper: &M) -> Option<End> {
        let n_events = self.sys.event_count();
        if let Err(msg) = self.opts.check(self.t, &self.y, self.t_end, n_events) {
            return Some((Status::InvalidInput, msg));
        }
        let (y0, t0) = (self.y, self.t);
        self.f = self.rhs(t0, &y0);
        self.out.start(&self.opts.output, t0, &y0);
        if !self.f.iter().all(|v| v.is_finite()) {
            let msg = format!("f(t0, y0) is not finite at t = {t0}");
            return Some((Status::NonFinite, msg));
        }
        self.events.reset(&*self.sys, t0, &y0, &self.f);
        let n_kinks = self.sys.kink_count();
        if n_kinks > MAX_KINKS {
            let msg = format!("{n_kinks} kink functions: at most {MAX_KINKS} are allowed");
            return Some((Status::InvalidInput, msg));
        }
        if stepper.lands_on_kinks() && stepper.is_adaptive() {
            self.plan.follow_kinks(n_kinks, &*self.sys, t0, &y0);
        }
        (self.t_end == t0).then(|| (Status::Success, String::new()))
    }

    /// The first step: the settings' `h0`, or Hairer's selection; a fixed step.
    fn first_step<M: Stepper<N>>(&mut self, stepper: &M) -> f64 {
        if !stepper.is_adaptive() {
            return self.opts.fixed_step;
        }
        let h_max = self.plan.h_max();
        match self.opts.h0 {
            Some(h0) => h0.min(h_max),
            None => self.select_step(stepper.order(), h_max),
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
            // `stiffness::PATIENT_STEPS`; `cushion-model/tests/statuses.rs`
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

    /// Hairer's estimate of `h |lambda|` for the accepted attempt of size `h`, for the
    /// stiffness test and for whether its dense output is stable (DOP853's is not near its
    /// boundary); not asked for where neither needs it.
    #[inline(always)]
    fn h_lambda<M: Stepper<N>>(
        &self,
        stepper: &M,
        stability: &Stability,
        h: f64,
        attempt: &Attempt<N>,
    ) -> Option<f64> {
        if self.opts.stiffness != StiffnessAction::Off || stability.dense_bound.is_finite() {
            stepper.stiffness_estimate(h, attempt)
        } else {
            None
        }
    }

    /// Attempt one step of size `h` from the current state and judge it by the error
    /// estimate (fixed-step methods accept every finite step).
    fn attempt<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        controller: &mut M::Controller,
        adaptive: bool,
        h: f64,
        attempt: &mut Attempt<N>,
    ) -> Tried {
        let (t, y, f0) = (self.t, self.y, self.f);
        let counted = Counted::new(&*self.sys);
        let outcome = stepper.step_into(&counted, t, &y, &f0, h, attempt);
        self.stats.rhs_evals += counted.evals();
        let failed = match outcome {
            Ok(()) if is_finite(attempt) => None,
            Ok(()) => Some(StepFailure::NonFinite),
            Err(failure) => Some(failure),
        };
        if let Some(failure) = failed {
            if !adaptive {
                let msg = match failure {
                    StepFailure::NonFinite => {
                        format!("non-finite state in the step from t = {t} (fixed step {h:e})")
                    }
                    other => format!("{other} in the step from t = {t} (fixed step {h:e})"),
                };
                return Tried::End(Status::NonFinite, msg);
            }
            self.stats.rejected += 1;
            if failure != StepFailure::NonFinite {
                self.stats.failed_solves += 1;
            }
            stepper.rejected();
            self.plan.rejected(h);
            return Tried::Retry(controller.after_failure(h, failure));
        }
        let mut h_new = h;
        let mut err_norm = None;
        if let Some(err) = &attempt.err {
            let en = match &attempt.err_low {
                None => self.weights.error_norm(err, &y, &attempt.y1),
                Some(err3) => {
                    let combined = self.weights.dop853_error_norm(err, err3, &y, &attempt.y1);
                    // DOP853's combined estimate, `err5^2 / sqrt(err5^2 + 0.01 err3^2)`, is
                    // built for smooth solutions: for a force that sets in like `delta^1.5`
                    // where the step starts it gives 0.29 of the true error, its fifth-order
                    // estimate alone 1.46 (`bench/dop853_onset.py`). Such a step is judged
                    // by the larger (cushion-model's
                    // `tests/peaks.rs::dop853_after_a_gentle_contact_onset`).
                    if self.since_restart.on_kink {
                        combined.max(self.weights.error_norm(err, &y, &attempt.y1))
                    } else {
                        combined
                    }
                }
            };
            let (accepted, mut hn) = controller.next(en, h);
            if !accepted && self.since_restart.fresh {
                hn = hn.min(retry_after_discontinuity(en, h));
            }
            if !accepted {
                self.stats.rejected += 1;
                stepper.rejected();
                self.plan.rejected(h);
                return Tried::Retry(hn);
            }
            h_new = hn;
            err_norm = Some(en);
        }
        self.stats.steps += 1;
        self.since_restart = SinceRestart {
            fresh: false,
            on_kink: false,
        };
        // What the method evaluates for accepted steps only (DOP853: f(y1), dense stages).
        let counted = Counted::new(&*self.sys);
        let completed = stepper.complete(&counted, t, &y, h, attempt);
        self.stats.rhs_evals += counted.evals();
        stepper.accepted();
        if completed && !is_finite(attempt) {
            self.t = t + h;
            self.y = attempt.y1;
            return Tried::End(
                Status::NonFinite,
                format!("f is not finite at the accepted state at t = {}", t + h),
            );
        }
        Tried::Accepted(h_new, err_norm)
    }

    /// The step just accepted is not kept but taken again from the same point
    /// (`step_guard.rs`): it counts as rejected, and where the run stood since the last
    /// restart is set back to `since_restart`, as it was before the step, so that the step
    /// taken again is judged as the first after the restart if this one was; for the restart
    /// steps, the attempt of size `h` was rejected.
    fn take_back(&mut self, since_restart: SinceRestart, h: f64) {
        self.stats.steps -= 1;
        self.stats.rejected += 1;
        self.since_restart = since_restart;
        self.plan.rejected(h);
    }

    /// Hairer's stiffness test on an accepted step from `t` of size `h`, with the method's
    /// estimate `h_lambda` of `h |lambda|`; the run's end when the options say to stop on
    /// stiffness.
    fn observe_stiffness(
        &mut self,
        stiffness: &mut StiffnessDetector,
        t: f64,
        h: f64,
        h_lambda: Option<f64>,
        attempt: &Attempt<N>,
    ) -> Option<End> {
        if self.opts.stiffness == StiffnessAction::Off {
            return None;
        }
        let since = stiffness.observe(t, h_lambda?)?;
        if !self.stats.stiff {
            self.stats.stiff = true;
            self.stats.stiff_since = Some(since);
        }
        if self.opts.stiffness != StiffnessAction::Stop {
            return None;
        }
        self.t = t + h;
        self.y = attempt.y1;
        let msg = format!(
            "the problem is stiff since t = {since} (h*lambda > {:.3} for {} steps)",
            stiffness.threshold(),
            crate::stiffness::STIFF_STEPS
        );
        Some((Status::Stiff, msg))
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
            (s.t_cut, s.y_cut)
        } else {
            (step.end(t), s.attempt.y1)
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
        self.sys.on_step(&step_seen, ctl);
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

    /// A handler cut the step of size `h` at `(t, y)` and changed the state or the regime:
    /// evaluate `f` and select the step size anew (the one learned after the same event the
    /// last time, or Hairer's, at most the controller's `h_new`). The run's end if `f` is not
    /// finite there.
    fn restart_after_event<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        controller: &mut M::Controller,
        t: f64,
        y: &State<N>,
        h: f64,
        h_new: f64,
    ) -> Result<f64, End> {
        stepper.restart();
        if !self.restart_at(t, y) {
            let msg = format!("f is not finite after the event at t = {t}");
            return Err((Status::NonFinite, msg));
        }
        let event = self.events.log.last().map(|e| (e.index, e.rising));
        self.since_restart.on_kink = stepper.lands_on_kinks()
            && (self.events.log.iter().rev())
                .take_while(|e| e.t == t)
                .any(|e| self.sys.kinked_at_event(e.index));
        let learned = self.plan.restart(event);
        if !stepper.is_adaptive() {
            return Ok(h);
        }
        controller.reset();
        Ok(match learned {
            Some(h_event) => h_event,
            None => {
                let h_max = self.plan.h_max();
                self.select_step(stepper.order(), h_max).min(h_new.max(h))
            }
        })
    }

    /// The step landed on the time stop `t`: the system switches regime there, and the method
    /// restarts. The run's end, if the handler ends it or `f` is not finite after it.
    fn take_time_stop<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        t: f64,
        mut y: State<N>,
        ctl: &mut Control,
    ) -> Result<(), End> {
        self.plan.pass_stop();
        self.stats.time_stops += 1;
        let action = self.sys.on_time_stop(t, &mut y, ctl);
        self.y = y;
        self.plan.add_stops(t, ctl);
        if action == EventAction::Stop || ctl.stop_requested {
            return Err((Status::StoppedByEvent, String::new()));
        }
        stepper.restart();
        if !self.restart_at(t, &y) {
            let msg = format!("f is not finite at the time stop t = {t}");
            return Err((Status::NonFinite, msg));
        }
        Ok(())
    }

    /// The next step's first slope at `(t, y)`: the method's last stage `f1` (FSAL), or
    /// evaluated here. The run's end if it is not finite.
    fn take_next_slope(&mut self, f1: Option<State<N>>, t: f64, y: &State<N>) -> Result<(), End> {
        self.f = match f1 {
            Some(f1) => f1,
            None => {
                let f1 = self.rhs(t, y);
                if !f1.iter().all(|v| v.is_finite()) {
                    let msg = format!("f is not finite at the accepted state at t = {t}");
                    return Err((Status::NonFinite, msg));
                }
                f1
            }
        };
        Ok(())
    }

    /// After a handler (event or time stop) at `(t, y)`: evaluate `f` and the event and kink
    /// functions anew there. Returns false if `f` is not finite.
    fn restart_at(&mut self, t: f64, y: &State<N>) -> bool {
        self.since_restart = SinceRestart {
            fresh: true,
            on_kink: false,
        };
        self.f = self.rhs(t, y);
        self.events.reset(&*self.sys, t, y, &self.f);
        self.plan.restart_kinks(&*self.sys, t, y);
        self.f.iter().all(|v| v.is_finite())
    }

    /// Hairer's initial step selection from the current state (one evaluation).
    fn select_step(&mut self, order: u32, h_max: f64) -> f64 {
        let (t, y, f) = (self.t, self.y, self.f);
        let w = self.weights;
        let sys = &*self.sys;
        let mut evals = 0;
        let h = initial_step(
            &y,
            &f,
            order,
            h_max,
            |v, yy| w.scaled_sq(v, yy),
            |h, y1| {
                evals += 1;
                sys.rhs(t + h, y1)
            },
        );
        self.stats.rhs_evals += evals;
        h
    }
}
