//! The trajectory recorder: an observer of a run, apart from the physics it records. It keeps
//! the scene at every accepted step's end, at every event, and at uniform sample times read from
//! each step's dense output; `simulate` composes it with the model (`observe.rs`) only when a
//! trajectory is asked for.

use cushion_ode::{Control, Method, Observer, State, Step};

use crate::early_end::Tail;
use crate::model::{to_point, Model};
use crate::trajectory::{Trajectory, TrajectoryPoint};

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
    pub fn take_events(&mut self, model: &Model) {
        for e in &model.log[self.events_seen..] {
            self.points.push(e.point);
        }
        self.events_seen = model.log.len();
    }

    /// The uniform samples inside an accepted step and its end, in the step's regime and
    /// robot segment (the model's observers have not moved on yet).
    fn record_step<const N: usize>(&mut self, model: &Model, step: &Step<'_, N>) {
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

    /// The tail's points in `(tail.t, t_to)` (`y_te`: the state where the tail begins): its
    /// uniform samples, or without them a ringing tail's 16 points per period. The uniform
    /// samples go on after `t_to` where the integration resumes there.
    pub fn record_tail(&mut self, model: &Model, tail: &Tail, y_te: &[f64], t_to: f64) {
        let te = tail.t;
        let spacing = match (self.sample_interval, tail.ringing_spacing()) {
            (Some(dt), _) => Some((dt, (self.next_sample / dt).round() as u64)),
            (None, Some(dt)) => Some((dt, (te / dt).floor() as u64 + 1)),
            (None, None) => None,
        };
        let Some((dt, mut k)) = spacing else {
            return;
        };
        loop {
            let ts = k as f64 * dt;
            if ts >= t_to {
                break;
            }
            if ts > te {
                self.points
                    .push(model.point_at(ts, &tail.state_at(model, y_te, ts)));
            }
            k += 1;
        }
        if self.sample_interval.is_some() {
            self.n_samples = k.saturating_sub(1);
            self.next_sample = k as f64 * dt;
        }
    }

    /// The recorded trajectory of a finished run whose final point is `end`. After an early end
    /// the uniform samples up to `t_end` come from the tail (`y_te`: the state at the early
    /// end); without uniform samples, a ringing tail is drawn with 16 points per period.
    pub fn finish(
        mut self,
        model: &Model,
        tail: Option<&Tail>,
        y_te: &[f64],
        t_end: f64,
        end: TrajectoryPoint,
    ) -> Trajectory {
        if let Some(tail) = tail {
            self.record_tail(model, tail, y_te, t_end);
            self.points.push(end);
        }
        let mut pts = self.points;
        pts.sort_by(|a, b| a.t.total_cmp(&b.t));
        // Keep both sides of a jump (kinks of the robot profile); drop exact duplicates.
        pts.dedup_by(|b, a| {
            a.values()
                .iter()
                .zip(b.values().iter())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        });
        Trajectory { points: pts }
    }
}

/// The recorder watches a run when a trajectory is asked for: every accepted step, and the
/// events the model logged at each instant, time stop and change of method.
impl<const N: usize> Observer<Model, N> for Recorder {
    #[inline]
    fn on_step(&mut self, model: &Model, step: &Step<'_, N>) {
        self.record_step(model, step);
    }

    #[inline]
    fn after_events(&mut self, model: &Model) {
        self.take_events(model);
    }

    #[inline]
    fn after_time_stop(&mut self, model: &Model, _t: f64, _y: &State<N>, _ctl: &mut Control) {
        self.take_events(model);
    }

    #[inline]
    fn after_switch(&mut self, model: &Model, _to: Method) {
        self.take_events(model);
    }
}
