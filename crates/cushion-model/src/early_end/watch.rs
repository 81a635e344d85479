//! The early end as an observer of a run. It reads the peaks so far (a ringing tail must not
//! change them), so it watches the run behind the peak sampler, as one observer with it: the
//! sampler sees each hook first, then the early end asks whether the run may end.

use cushion_ode::{Control, Observer, State, Step};

use super::EarlyEnd;
use crate::model::Model;
use crate::peaks::PeakSampler;

/// The peak sampler and, when `solver.early_end` is on, the early end behind it.
pub(crate) struct PeaksThenEarlyEnd<'a> {
    pub peaks: &'a mut PeakSampler,
    pub early_end: Option<&'a mut EarlyEnd>,
}

impl PeaksThenEarlyEnd<'_> {
    /// Whether the early end (if on) ends the run at `(t, y)`.
    fn ends_early(&mut self, model: &Model, t: f64, y: &[f64]) -> bool {
        let peaks = &self.peaks.peaks;
        self.early_end
            .as_mut()
            .is_some_and(|e| e.check(model, peaks, t, y))
    }
}

impl<const N: usize> Observer<Model, N> for PeaksThenEarlyEnd<'_> {
    #[inline]
    fn on_step(&mut self, model: &Model, step: &Step<'_, N>) {
        Observer::<Model, N>::on_step(self.peaks, model, step);
    }

    #[inline]
    fn after_step(&mut self, model: &Model, step: &Step<'_, N>, ctl: &mut Control) {
        if self.ends_early(model, step.t1, step.y1.as_slice()) {
            ctl.stop();
        }
    }

    #[inline]
    fn after_events(&mut self, model: &Model) {
        Observer::<Model, N>::after_events(self.peaks, model);
    }

    #[inline]
    fn before_time_stop(&mut self, model: &Model) {
        Observer::<Model, N>::before_time_stop(self.peaks, model);
    }

    #[inline]
    fn after_time_stop(&mut self, model: &Model, t: f64, y: &State<N>, ctl: &mut Control) {
        // a robot kink may leave nothing to change (the robot stands, or cruises on)
        if model.time_stop_was_kink && self.ends_early(model, t, y.as_slice()) {
            ctl.stop();
        }
    }
}
