//! Where steps start from: the run's start and its first step, a restart after an event
//! or at a time stop, the next step's first slope, and Hairer's initial step selection.

use super::{End, Integration, SinceRestart};
use crate::controller::{initial_step, Controller};
use crate::kinks::MAX_KINKS;
use crate::observer::Observer;
use crate::solution::Status;
use crate::stepper::Stepper;
use crate::system::{Control, EventAction, OdeSystem};
use crate::State;

impl<S: OdeSystem<N>, O: Observer<S, N>, const N: usize> Integration<'_, S, O, N> {
    /// The run's start: the settings checked, `f`, the output and the event and kink
    /// functions at `(t0, y0)`. The run's end if it ends there.
    pub(super) fn start<M: Stepper<N>>(&mut self, stepper: &M) -> Option<End> {
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
    pub(super) fn first_step<M: Stepper<N>>(&mut self, stepper: &M) -> f64 {
        if !stepper.is_adaptive() {
            return self.opts.fixed_step;
        }
        let h_max = self.plan.h_max();
        match self.opts.h0 {
            Some(h0) => h0.min(h_max),
            None => self.select_step(stepper.order(), h_max),
        }
    }

    /// A handler cut the step of size `h` at `(t, y)` and changed the state or the regime:
    /// evaluate `f` and select the step size anew (the one learned after the same event the
    /// last time, or Hairer's, at most the controller's `h_new`). The run's end if `f` is not
    /// finite there.
    pub(super) fn restart_after_event<M: Stepper<N>>(
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
    pub(super) fn take_time_stop<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        t: f64,
        mut y: State<N>,
        ctl: &mut Control,
    ) -> Result<(), End> {
        self.plan.pass_stop();
        self.stats.time_stops += 1;
        self.observer.before_time_stop(&*self.sys);
        let action = self.sys.on_time_stop(t, &mut y, ctl);
        self.observer.after_time_stop(&*self.sys, t, &y, ctl);
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
    pub(super) fn take_next_slope(
        &mut self,
        f1: Option<State<N>>,
        t: f64,
        y: &State<N>,
    ) -> Result<(), End> {
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
    pub(super) fn restart_at(&mut self, t: f64, y: &State<N>) -> bool {
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
    pub(super) fn select_step(&mut self, order: u32, h_max: f64) -> f64 {
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
