//! The trajectory recorder: an observer of a run, apart from the physics it records. It keeps
//! the scene at every accepted step's end, at every event, and at uniform sample times read from
//! each step's dense output; `simulate` composes it with the model ([`Observed`]) only when a
//! trajectory is asked for.

use cushion_ode::{Control, Direction, EventAction, Matrix, Method, OdeSystem, State, Step};

use crate::model::{to_point, Model};
use crate::trajectory::TrajectoryPoint;

/// Recorded points, and where the uniform samples stand.
pub(crate) struct Recorder {
    pub points: Vec<TrajectoryPoint>,
    /// Uniform samples every this many seconds (besides steps and events).
    pub sample_interval: Option<f64>,
    /// Next uniform sample time, `(n_samples + 1) * sample_interval` (no accumulated rounding).
    pub next_sample: f64,
    n_samples: u64,
    /// Entries of the model's event log already recorded.
    events_seen: usize,
}

impl Recorder {
    /// Start at the model's initial state.
    pub fn new(model: &Model, sample_interval: Option<f64>) -> Recorder {
        let sample_interval = sample_interval.filter(|dt| *dt > 0.0 && dt.is_finite());
        Recorder {
            points: vec![model.point_at(0.0, &model.y0)],
            sample_interval,
            next_sample: sample_interval.unwrap_or(0.0),
            n_samples: 0,
            events_seen: model.log.len(),
        }
    }

    /// The scene at the events the model logged since the last call.
    fn take_events(&mut self, model: &Model) {
        for e in &model.log[self.events_seen..] {
            self.points.push(e.point);
        }
        self.events_seen = model.log.len();
    }

    /// The uniform samples inside an accepted step and its end, in the step's regime and
    /// robot segment (the model's observers have not moved on yet).
    fn on_step<const N: usize>(&mut self, model: &Model, step: &Step<'_, N>) {
        let (t0, t1) = (step.t0, step.t1);
        let seg = *model.robot.segment_at(0.5 * (t0 + t1));
        let r = *model.step_regime();
        if let Some(dt) = self.sample_interval {
            while self.next_sample < t1 {
                let ts = self.next_sample;
                let e = model.eval(ts, step.at(ts).as_slice(), &seg, &r);
                self.points.push(to_point(ts, &e));
                self.n_samples += 1;
                self.next_sample = (self.n_samples + 1) as f64 * dt;
            }
        }
        let e1 = model.eval(t1, step.y1.as_slice(), &seg, &r);
        self.points.push(to_point(t1, &e1));
    }
}

/// The model with its optional observers, as the integrator sees it: the physics answers
/// every question about the system, the observers see every step and event.
pub(crate) struct Observed {
    pub model: Model,
    pub recorder: Option<Recorder>,
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
        if let Some(r) = self.recorder.as_mut() {
            r.take_events(&self.model);
        }
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
    fn event_direction(&self, i: usize) -> Direction {
        OdeSystem::<N>::event_direction(&self.model, i)
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
        if let Some(r) = self.recorder.as_mut() {
            r.take_events(&self.model);
        }
        action
    }
    #[inline]
    fn on_time_stop(&mut self, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        let action = OdeSystem::<N>::on_time_stop(&mut self.model, t, y, ctl);
        if let Some(r) = self.recorder.as_mut() {
            r.take_events(&self.model);
        }
        action
    }
    #[inline]
    fn on_step(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        if let Some(r) = self.recorder.as_mut() {
            r.on_step(&self.model, step);
        }
        OdeSystem::<N>::on_step(&mut self.model, step, ctl);
    }
}
