//! A time stop scheduled by an event, as a sensor and a robot's dead time do: `x' = v`,
//! `v' = a`, where `a` switches from 0 to -1 at a time stop that the event `x` rising through 1
//! schedules `delay` later. `df/dt = 0` in each regime.

use crate::system::{Control, Direction, EventAction, OdeSystem};
use crate::State;

pub struct ScheduledBrake {
    pub delay: f64,
    pub braking: bool,
    /// When the brake was scheduled for (the event's time plus `delay`).
    pub stop_time: Option<f64>,
}

impl ScheduledBrake {
    pub fn new(delay: f64) -> ScheduledBrake {
        ScheduledBrake {
            delay,
            braking: false,
            stop_time: None,
        }
    }
}

impl OdeSystem<2> for ScheduledBrake {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], if self.braking { -1.0 } else { 0.0 })
    }
    fn time_derivative(&self, _t: f64, _y: &State<2>) -> Option<State<2>> {
        Some(State::<2>::zeros())
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<2>, g: &mut [f64]) {
        g[0] = y[0] - 1.0;
    }
    fn event_direction(&self, _i: usize) -> Direction {
        Direction::Rising
    }
    fn on_event(&mut self, _i: usize, t: f64, _y: &mut State<2>, ctl: &mut Control) -> EventAction {
        self.stop_time = Some(t + self.delay);
        ctl.add_time_stop(t + self.delay);
        EventAction::Continue
    }
    fn on_time_stop(&mut self, _t: f64, _y: &mut State<2>, _ctl: &mut Control) -> EventAction {
        self.braking = true;
        EventAction::Continue
    }
}
