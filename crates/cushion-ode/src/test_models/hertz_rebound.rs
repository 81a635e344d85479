//! A lone elastic Hertz rebound after a flight: a body flies at `v0` for 5 ms onto a wall,
//! `x'' = (K/m) (-x)^1.5` while in contact, with no other force. Energy is conserved, so it
//! leaves the wall as fast as it hit it. The contact begins and ends as events that restart
//! the integration; the force sets in and vanishes like `delta^1.5` at them, and its end is
//! declared a kink of `f` ([`OdeSystem::kinked_at_event`]) unless told not to.

use crate::{
    solve, Control, Direction, EventAction, Method, OdeSystem, SolverOptions, State, Tolerance,
};

/// The flight before the contact (s).
const FLIGHT: f64 = 5e-3;

/// `x` the gap to the wall (negative: in contact), `v` its rate.
pub struct HertzRebound {
    /// Wall stiffness over the body's mass (N/m^1.5/kg).
    pub k_over_m: f64,
    pub in_contact: bool,
    /// Whether it says that `f` is kinked where the contact ends.
    pub declares_kink: bool,
}

impl OdeSystem<2> for HertzRebound {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        let push = if self.in_contact {
            self.k_over_m * (-y[0]).max(0.0).powf(1.5)
        } else {
            0.0
        };
        State::<2>::new(y[1], push)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<2>, g: &mut [f64]) {
        g[0] = y[0];
    }
    fn kinked_at_event(&self, _i: usize) -> bool {
        self.declares_kink && self.in_contact
    }
    fn event_direction(&self, _i: usize) -> Direction {
        if self.in_contact {
            Direction::Rising
        } else {
            Direction::Falling
        }
    }
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        _y: &mut State<2>,
        _ctl: &mut Control,
    ) -> EventAction {
        if self.in_contact {
            return EventAction::Stop;
        }
        self.in_contact = true;
        EventAction::Restart
    }
}

/// One rebound at `v0` (m/s) under `method` at `rtol` (atol `rtol / 1000`): the rebound
/// speed's relative error and the evaluations; `None` if the body never left the wall.
pub fn rebound(
    method: Method,
    declares_kink: bool,
    k_over_m: f64,
    v0: f64,
    rtol: f64,
) -> Option<(f64, u64)> {
    // Hertz: the contact lasts 2.9432 d / v0, d the deepest penetration
    let depth = (1.25 * v0 * v0 / k_over_m).powf(0.4);
    let contact = 2.9432 * depth / v0;
    let opts = SolverOptions {
        method,
        rtol: Tolerance::Scalar(rtol),
        atol: Tolerance::Scalar(rtol * 1e-3),
        ..Default::default()
    };
    let mut body = HertzRebound {
        k_over_m,
        in_contact: false,
        declares_kink,
    };
    let sol = solve(
        &mut body,
        0.0,
        State::<2>::new(v0 * FLIGHT, -v0),
        FLIGHT + 3.0 * contact,
        &opts,
    );
    let lift_off = sol.events.get(1)?;
    Some(((lift_off.state[1] / v0 - 1.0).abs(), sol.stats.rhs_evals))
}
