//! What observes a run, apart from the physics it observes: each observer sees every accepted
//! step and every event, and none of them changes the solution.
//!
//! - `peaks/`: the peaks of `|F_r|`, `F_c`, the stroke and the gas pressure;
//! - `early_end/`: the early end, which stops the run once what is left of it is known in
//!   closed form (`early_end/tail.rs`); off with `solver.early_end = false`;
//! - `observe/recorder.rs`: the trajectory, when one is asked for.
//!
//! [`Watchers`] is them as one observer of the integrator (`cushion_ode::Observer`), beside
//! the model, which answers every question about the system (right-hand side, Jacobian, event
//! functions and handlers): OrdinaryDiffEq's callbacks beside its problem. A new observer is a
//! file here and a line in each hook it needs.

pub(crate) mod recorder;

use cushion_ode::{Control, Method, Observer, State, Step};

use crate::early_end::EarlyEnd;
use crate::model::Model;
use crate::peaks::PeakSampler;
use recorder::Recorder;

/// The model with its observers: what a run keeps.
pub(crate) struct Observed {
    pub model: Model,
    pub peaks: PeakSampler,
    pub early_end: Option<EarlyEnd>,
    pub recorder: Option<Recorder>,
}

impl Observed {
    /// The model and, apart, its observers, for `cushion_ode::solve_observed`.
    pub(crate) fn split(&mut self) -> (&mut Model, Watchers<'_>) {
        let watchers = Watchers {
            peaks: &mut self.peaks,
            early_end: &mut self.early_end,
            recorder: &mut self.recorder,
        };
        (&mut self.model, watchers)
    }
}

/// The observers of one solve.
pub(crate) struct Watchers<'a> {
    peaks: &'a mut PeakSampler,
    early_end: &'a mut Option<EarlyEnd>,
    recorder: &'a mut Option<Recorder>,
}

impl Watchers<'_> {
    /// The events the model logged go to the recorder.
    fn record_events(&mut self, model: &Model) {
        if let Some(r) = self.recorder.as_mut() {
            r.take_events(model);
        }
    }

    /// Whether the early end (if on) ends the run at `(t, y)`.
    fn ends_early(&mut self, model: &Model, t: f64, y: &[f64]) -> bool {
        let peaks = &self.peaks.peaks;
        self.early_end
            .as_mut()
            .is_some_and(|e| e.check(model, peaks, t, y))
    }
}

impl<const N: usize> Observer<Model, N> for Watchers<'_> {
    #[inline]
    fn on_step(&mut self, model: &Model, step: &Step<'_, N>) {
        if let Some(r) = self.recorder.as_mut() {
            r.on_step(model, step);
        }
        self.peaks.on_step(model, step);
    }

    #[inline]
    fn after_step(&mut self, model: &Model, step: &Step<'_, N>, ctl: &mut Control) {
        if self.ends_early(model, step.t1, step.y1.as_slice()) {
            ctl.stop();
        }
    }

    #[inline]
    fn after_events(&mut self, model: &Model) {
        self.peaks.after_event();
        self.record_events(model);
    }

    #[inline]
    fn before_time_stop(&mut self, model: &Model) {
        self.peaks.before_time_stop(model);
    }

    #[inline]
    fn after_time_stop(&mut self, model: &Model, t: f64, y: &State<N>, ctl: &mut Control) {
        // a robot kink may leave nothing to change (the robot stands, or cruises on)
        if model.time_stop_was_kink && self.ends_early(model, t, y.as_slice()) {
            ctl.stop();
        }
        self.record_events(model);
    }

    #[inline]
    fn after_switch(&mut self, model: &Model, _to: Method) {
        self.record_events(model);
    }
}
