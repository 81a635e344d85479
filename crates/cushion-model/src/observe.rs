//! What observes a run, apart from the physics it observes: each observer sees every accepted
//! step and every event, and none of them changes the solution.
//!
//! - `peaks/`: the peaks of `|F_r|`, `F_c`, the stroke and the gas pressure;
//! - `early_end/`: the early end, which stops the run once what is left of it is known in
//!   closed form (`early_end/tail.rs`); off with `solver.early_end = false`;
//! - `observe/recorder.rs`: the trajectory, when one is asked for.
//!
//! [`Observed`] composes them with the model for the integrator, in the shape of
//! OrdinaryDiffEq's callbacks beside its problem: the model answers every question about the
//! system (right-hand side, Jacobian, event functions and handlers), the observers watch.

pub(crate) mod recorder;

use cushion_ode::{Control, Direction, EventAction, Matrix, Method, OdeSystem, State, Step};

use crate::early_end::EarlyEnd;
use crate::model::Model;
use crate::peaks::PeakSampler;
use recorder::Recorder;

/// The model with its observers, as the integrator sees it.
pub(crate) struct Observed {
    pub model: Model,
    pub peaks: PeakSampler,
    pub early_end: Option<EarlyEnd>,
    pub recorder: Option<Recorder>,
}

impl Observed {
    /// The events the model logged go to the recorder.
    fn record_events(&mut self) {
        if let Some(r) = self.recorder.as_mut() {
            r.take_events(&self.model);
        }
    }

    /// Whether the early end (if on) ends the run at `(t, y)`.
    fn ends_early(&mut self, t: f64, y: &[f64]) -> bool {
        let (model, peaks) = (&self.model, &self.peaks.peaks);
        self.early_end
            .as_mut()
            .is_some_and(|e| e.check(model, peaks, t, y))
    }
}

impl<const N: usize> OdeSystem<N> for Observed {
    #[inline]
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        OdeSystem::<N>::rhs(&self.model, t, y)
    }
    #[inline]
    fn jacobian(&self, t: f64, y: &State<N>) -> Option<Matrix<N>> {
        OdeSystem::<N>::jacobian(&self.model, t, y)
    }
    #[inline]
    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        OdeSystem::<N>::time_derivative(&self.model, t, y)
    }
    #[inline]
    fn jacobians(&self, t: f64, y: &State<N>) -> (Option<Matrix<N>>, Option<State<N>>) {
        OdeSystem::<N>::jacobians(&self.model, t, y)
    }
    #[inline]
    fn on_switch(&mut self, t: f64, y: &State<N>, to: Method) {
        OdeSystem::<N>::on_switch(&mut self.model, t, y, to);
        self.record_events();
    }
    #[inline]
    fn event_count(&self) -> usize {
        OdeSystem::<N>::event_count(&self.model)
    }
    #[inline]
    fn events(&self, t: f64, y: &State<N>, g: &mut [f64]) {
        OdeSystem::<N>::events(&self.model, t, y, g)
    }
    #[inline]
    fn event(&self, i: usize, t: f64, y: &State<N>) -> f64 {
        OdeSystem::<N>::event(&self.model, i, t, y)
    }
    #[inline]
    fn kink_count(&self) -> usize {
        OdeSystem::<N>::kink_count(&self.model)
    }
    #[inline]
    fn kink(&self, i: usize, t: f64, y: &State<N>) -> f64 {
        OdeSystem::<N>::kink(&self.model, i, t, y)
    }
    #[inline]
    fn event_direction(&self, i: usize) -> Direction {
        OdeSystem::<N>::event_direction(&self.model, i)
    }
    #[inline]
    fn kinked_at_event(&self, i: usize) -> bool {
        OdeSystem::<N>::kinked_at_event(&self.model, i)
    }
    #[inline]
    fn event_chord_bound(&self, i: usize, t0: f64, t1: f64, dev: &State<N>) -> Option<f64> {
        OdeSystem::<N>::event_chord_bound(&self.model, i, t0, t1, dev)
    }
    #[inline]
    fn event_chord_bounds(&self, t0: f64, t1: f64, dev: &State<N>, bounds: &mut [f64]) {
        OdeSystem::<N>::event_chord_bounds(&self.model, t0, t1, dev, bounds)
    }
    #[inline]
    fn on_event(&mut self, i: usize, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        let action = OdeSystem::<N>::on_event(&mut self.model, i, t, y, ctl);
        self.peaks.after_event();
        self.record_events();
        action
    }
    #[inline]
    fn on_time_stop(&mut self, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        self.peaks.before_time_stop(&self.model);
        let kink = self.model.time_stop(t, y.as_slice(), ctl);
        // a robot kink may leave nothing to change (the robot stands, or cruises on)
        let action = if kink && self.ends_early(t, y.as_slice()) {
            EventAction::Stop
        } else {
            EventAction::Continue
        };
        self.record_events();
        action
    }
    #[inline]
    fn on_step(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        if let Some(r) = self.recorder.as_mut() {
            r.on_step(&self.model, step);
        }
        self.peaks.on_step(&self.model, step);
        OdeSystem::<N>::on_step(&mut self.model, step, ctl);
        if self.ends_early(step.t1, step.y1.as_slice()) {
            ctl.stop();
        }
    }
}
