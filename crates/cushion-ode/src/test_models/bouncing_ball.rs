//! A ball falling under gravity onto the floor `x = 0`, bouncing with restitution `e`.
//! Event: `x` falls through 0; action: `v <- -e v`, restart.

use crate::{solve, Control, Direction, EventAction, OdeSystem, Solution, SolverOptions, State};

pub struct BouncingBall {
    pub gravity: f64,
    pub restitution: f64,
    /// Stop after this many bounces (0: never).
    pub stop_after: usize,
    pub bounces: usize,
}

/// The drop every method is checked on: from rest at 1 m, `g = 9.81`, restitution 0.8, stopped
/// at the tenth bounce; the solution under `opts` and the ten bounce times in closed form.
pub fn ten_bounces(opts: &SolverOptions) -> (Solution<2>, Vec<f64>) {
    let mut ball = BouncingBall {
        gravity: 9.81,
        restitution: 0.8,
        stop_after: 10,
        bounces: 0,
    };
    let exact = ball.bounce_times(1.0, 10);
    let sol = solve(&mut ball, 0.0, State::<2>::new(1.0, 0.0), 100.0, opts);
    (sol, exact)
}

impl BouncingBall {
    /// Bounce times in closed form for a drop from rest at height `h0`.
    pub fn bounce_times(&self, h0: f64, n: usize) -> Vec<f64> {
        let t1 = (2.0 * h0 / self.gravity).sqrt();
        let v1 = self.gravity * t1;
        let mut out = vec![t1];
        let mut t = t1;
        let mut v = v1;
        for _ in 1..n {
            v *= self.restitution;
            t += 2.0 * v / self.gravity;
            out.push(t);
        }
        out
    }
}

impl OdeSystem<2> for BouncingBall {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], -self.gravity)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<2>, g: &mut [f64]) {
        g[0] = y[0];
    }
    fn event_direction(&self, _i: usize) -> Direction {
        Direction::Falling
    }
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        y: &mut State<2>,
        _ctl: &mut Control,
    ) -> EventAction {
        self.bounces += 1;
        y[0] = 0.0;
        y[1] *= -self.restitution;
        if self.stop_after > 0 && self.bounces >= self.stop_after {
            EventAction::Stop
        } else {
            EventAction::Restart
        }
    }
}
