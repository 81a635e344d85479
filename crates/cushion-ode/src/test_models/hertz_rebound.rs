//! A body against a Hertzian wall: `x'' = (K/m) (-x)^1.5 - g` while in contact (`x < 0`),
//! `-g` in flight. The contact begins and ends as events that restart the integration; the
//! force sets in and vanishes like `delta^1.5` at them, and its end may be declared a kink of
//! `f` ([`OdeSystem::kinked_at_event`]). [`rebound`]: a lone elastic rebound after a flight at
//! `v0` with no gravity, which must leave the wall as fast as it hit it;
//! `tests/integrator/stiff_contact.rs` drops a ball on a steel-like floor and lets it bounce.

use crate::{
    solve, Control, Direction, EventAction, Method, OdeSystem, SolverOptions, State, Tolerance,
};

/// The flight before the contact (s).
const FLIGHT: f64 = 5e-3;

/// `x` the gap to the wall (negative: in contact), `v` its rate.
pub struct HertzRebound {
    /// Wall stiffness over the body's mass (N/m^1.5/kg).
    pub k_over_m: f64,
    /// Acceleration towards the wall (m/s^2).
    pub gravity: f64,
    pub in_contact: bool,
    /// Whether it says that `f` is kinked where the contact ends.
    pub declares_kink: bool,
    /// Whether the run goes on after a lift-off (else it stops there).
    pub keeps_bouncing: bool,
}

impl OdeSystem<2> for HertzRebound {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        let push = if self.in_contact {
            self.k_over_m * (-y[0]).max(0.0).powf(1.5)
        } else {
            0.0
        };
        State::<2>::new(y[1], push - self.gravity)
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
        if self.in_contact && !self.keeps_bouncing {
            return EventAction::Stop;
        }
        self.in_contact = !self.in_contact;
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
        gravity: 0.0,
        in_contact: false,
        declares_kink,
        keeps_bouncing: false,
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
