//! The model as the integrator sees it: right-hand side, event functions and handlers, time
//! stops and the per-step hook (`cushion_ode::OdeSystem`).

use super::events::{EventKinematics, EV_BACK, EV_CAVITATION, EV_FWD, EV_OBJECT, EV_SENSOR};
use super::{Model, Regime};
use crate::config::Module;
use crate::physics::Segment;
use cushion_ode::{Control, Direction, EventAction, Matrix, Method, OdeSystem, State, Step};

impl Model {
    /// `f(t, y)` in the robot segment `seg` and the regime `r` (the right-hand side is this in
    /// the current ones).
    #[inline(always)]
    pub(crate) fn rates<const N: usize>(
        &self,
        t: f64,
        y: &State<N>,
        seg: &Segment,
        r: &Regime,
    ) -> State<N> {
        let e = self.eval_inline(t, y.as_slice(), seg, r);
        let v_p = if r.obj_stuck { 0.0 } else { e.v_p };
        // In the order of `Rate` (`Zero` and the padding to 16, so that an index needs no bounds
        // check, are zeros).
        let rates = [
            e.v_t,
            e.a_t,
            e.dp_m,
            e.flow,
            v_p,
            e.a_p,
            e.p_work,
            e.p_orifice + e.p_friction + e.p_contact + e.p_plane,
            e.p_liquid,
            e.f_c,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        let of = &self.layout.rates;
        State::<N>::from_fn(|j, _| rates[usize::from(of[j] & 15)])
    }
}

impl<const N: usize> OdeSystem<N> for Model {
    #[inline]
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.rates(t, y, self.robot.current(), &self.regime)
    }

    fn jacobian(&self, t: f64, y: &State<N>) -> Option<Matrix<N>> {
        Some(self.jacobians(t, y, &self.regime).0)
    }

    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        Some(self.jacobians(t, y, &self.regime).1)
    }

    fn jacobians(&self, t: f64, y: &State<N>) -> (Option<Matrix<N>>, Option<State<N>>) {
        let (jac, dfdt) = Model::jacobians(self, t, y, &self.regime);
        (Some(jac), Some(dfdt))
    }

    fn event_count(&self) -> usize {
        self.n_events
    }

    fn events(&self, t: f64, y: &State<N>, g: &mut [f64]) {
        let y = y.as_slice();
        let k = EventKinematics::at(self, t, y);
        let mut i = 0;
        self.event_set.visit(|kind| {
            if let Some(gi) = g.get_mut(i) {
                *gi = self.event_value(kind, t, y, &k);
            }
            i += 1;
        });
    }

    fn event(&self, i: usize, t: f64, y: &State<N>) -> f64 {
        let y = y.as_slice();
        let k = EventKinematics::at(self, t, y);
        self.event_value(self.events[i], t, y, &k)
    }

    fn event_chord_bound(&self, i: usize, t0: f64, t1: f64, dev: &State<N>) -> Option<f64> {
        let kind = *self.events.get(i)?;
        self.event_straying(kind, t1 - t0, dev.as_slice())
    }

    fn event_chord_bounds(&self, t0: f64, t1: f64, dev: &State<N>, bounds: &mut [f64]) {
        let dev = dev.as_slice();
        let mut i = 0;
        self.event_set.visit(|kind| {
            if let Some(b) = bounds.get_mut(i) {
                *b = self.event_straying(kind, t1 - t0, dev).unwrap_or(f64::NAN);
            }
            i += 1;
        });
    }

    /// The incompressible hydraulic module's orifice drop `sd |sd|` has a jump in its second
    /// derivative where the tool's speed relative to the flange, `sd`, changes sign: each
    /// time the tool turns, on every half period of its ringing. Its one kink function is
    /// `sd` (`cushion_ode::kinks`). The compressible liquid's flow law is laminar, and
    /// smooth, through zero.
    fn kink_count(&self) -> usize {
        usize::from(self.p.module == Module::Hydraulic && self.layout.liquid.is_none())
    }

    fn kink(&self, _i: usize, t: f64, y: &State<N>) -> f64 {
        let (_, v_r, _) = self.robot.current().at(t);
        self.layout.tool.map_or(0.0, |i| v_r - y[i + 1])
    }

    fn event_direction(&self, i: usize) -> Direction {
        // a contact's penetration rises through zero to begin and falls to end; the cavitation
        // margin falls to begin and rises to end
        let falling_if = |on: bool| {
            if on {
                Direction::Falling
            } else {
                Direction::Rising
            }
        };
        let r = &self.regime;
        match self.events.get(i).copied() {
            Some(EV_SENSOR) => Direction::Rising,
            Some(EV_OBJECT) => falling_if(r.obj_contact),
            Some(EV_FWD) => falling_if(r.fwd),
            Some(EV_BACK) => falling_if(r.back),
            Some(EV_CAVITATION) => falling_if(!r.cavitating),
            _ => Direction::Both,
        }
    }

    /// A contact's penetration while the contact is on (and its force not released): the
    /// Hertz term `k d^1.5`, with its Hunt–Crossley damping, has an infinite second derivative
    /// where `d` is zero. That is the contact's end before its handler, and, after an onset's
    /// handler, the point the run restarts from. Every other crossing leaves the current
    /// regime's `f` smooth: an onset switches the force on only in its handler, and the
    /// release, cavitation, stick and sensor laws change only with the regime.
    fn kinked_at_event(&self, i: usize) -> bool {
        let r = &self.regime;
        match self.events.get(i).copied() {
            Some(EV_OBJECT) => r.obj_contact && !r.obj_released,
            Some(EV_FWD) => r.fwd && !r.stop_released,
            Some(EV_BACK) => r.back && !r.stop_released,
            _ => false,
        }
    }

    fn on_event(&mut self, i: usize, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        let kind = self.events[i];
        self.handle_event(kind, t, y.as_mut_slice(), ctl)
    }

    fn on_time_stop(&mut self, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        self.time_stop_was_kink = self.time_stop(t, y.as_slice(), ctl);
        EventAction::Continue
    }

    /// A change of method under `solver.method = "auto"` is logged as an event
    /// (`switch_to_rodas`, `switch_to_dp5`): it tells where the scene was stiff.
    fn on_switch(&mut self, t: f64, y: &State<N>, to: Method) {
        let name = match to {
            Method::Rodas => "switch_to_rodas",
            _ => "switch_to_dp5",
        };
        self.log_event(name, t, y.as_slice());
    }

    /// The step is over: the regime its handlers set is the next step's.
    fn on_step(&mut self, _step: &Step<'_, N>, _ctl: &mut Control) {
        self.step_regime = self.regime;
    }
}

impl Model {
    /// A time stop at `t`: the robot brakes (the sensor's dead time is over) or reaches a kink
    /// of its profile. Returns whether it was a kink (the robot stands, or starts to cruise),
    /// after which nothing may be left to change (`early_end/`).
    pub(crate) fn time_stop(&mut self, t: f64, y: &[f64], ctl: &mut Control) -> bool {
        if let Some(tb) = self.pending_brake {
            if (t - tb).abs() <= 1e-12 * (1.0 + tb.abs()) {
                self.pending_brake = None;
                self.brake_now(t, y, ctl);
                return false;
            }
        }
        match self.robot.on_time(t) {
            Some(name) => {
                self.log_event(name, t, y);
                true
            }
            None => false,
        }
    }
}
