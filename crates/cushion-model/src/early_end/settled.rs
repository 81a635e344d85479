//! The settled tail: the robot stands, the tool has settled (stuck by dry friction, or its
//! speed relative to the robot below `100 atol` m/s and its acceleration below `1000 atol`
//! m/s^2), and the object is out of contact and either free and not slower than the tool or
//! stuck on the plane. Nothing can change any more: the state at `t_end` is the state now, the
//! object flying on.

use std::cell::OnceCell;

use super::tail::TailKind;
use crate::model::Model;
use crate::Scene;

/// The settled tail's test: below these the tool has settled.
pub(super) struct Settled {
    /// Relative speed (m/s) and acceleration (m/s^2).
    speed: f64,
    acceleration: f64,
}

impl Settled {
    pub fn new(scene: &Scene) -> Settled {
        let atol = scene.solver.atol;
        Settled {
            speed: 100.0 * atol,
            acceleration: 1000.0 * atol,
        }
    }

    /// The settled tail from `(t, y)`, if the robot stands and nothing can change any more (see
    /// the module docs).
    pub fn tail(&self, m: &Model, t: f64, y: &[f64]) -> Option<TailKind> {
        if m.regime.obj_contact || !m.robot.stopped() {
            return None;
        }
        let seg = *m.robot.current();
        // the physics at (t, y), computed once, and only where a test needs it: a tool still
        // bouncing on its stop under a standing robot fails the settling test on its speed
        // relative to the robot, `sd = v_r - v_t`, which the state gives as `Eval` does
        let physics = OnceCell::new();
        let e = || *physics.get_or_init(|| m.eval(t, y, &seg, &m.regime));
        let tool_settled = match m.layout.tool {
            None => true,
            Some(i) => {
                m.regime.tool_stuck
                    || ((seg.at(t).1 - y[i + 1]).abs() <= self.speed
                        && e().a_t.abs() <= self.acceleration)
            }
        };
        let object_done = || match m.layout.object {
            None => true,
            Some(_) if m.p.mu_n > 0.0 => m.regime.obj_stuck,
            Some(_) => {
                let e = e();
                e.v_p >= e.v_t.max(0.0)
            }
        };
        (tool_settled && object_done()).then_some(TailKind::Settled)
    }
}
