//! The early end: an observer that ends a run once nothing can change any more, and keeps what
//! is left of it as a [`Tail`] known in closed form (`tail.rs`).
//!
//! Once the robot stands, the tool has settled (stuck by dry friction, or its relative speed
//! below `100 atol` m/s and its acceleration below `1000 atol` m/s^2), and the object is out of
//! contact and either free and not slower than the tool or stuck on the plane, nothing can
//! change any more ([`TailKind::Settled`]). The same holds while the robot cruises on with no
//! brake before `t_end` (its sensor never switched, or the dead time ends after the run), the
//! object free and not slower than the tool, and the tool stuck short of the sensor or at rest
//! on its stop (`resting.rs`; [`TailKind::Riding`]). Failing that, the run may end once only the
//! tool's small ringing on its stop is left (`ringing_tail.rs`; [`TailKind::Ringing`]).

use std::cell::OnceCell;

use crate::model::Model;
use crate::peaks::Peaks;
use crate::physics::Phase;
use crate::ringing_tail::StopRinging;
use crate::tail::{Tail, TailKind};
use crate::Scene;

/// The early-end observer (`solver.early_end`), with the ringing tail's search
/// (`solver.ringing_tail`).
pub(crate) struct EarlyEnd {
    /// The tool has settled below these relative speed (m/s) and acceleration (m/s^2).
    settle_v: f64,
    settle_a: f64,
    /// The tool on its stop: its equilibria, its rest while the robot cruises, its ringing.
    stop: StopRinging,
    /// The run's tail, once it has ended early.
    pub tail: Option<Tail>,
}

impl EarlyEnd {
    pub fn new(scene: &Scene) -> EarlyEnd {
        let atol = scene.solver.atol;
        EarlyEnd {
            settle_v: 100.0 * atol,
            settle_a: 1000.0 * atol,
            stop: StopRinging::new(scene),
            tail: None,
        }
    }

    /// Whether the run may end at `(t, y)` (see the module docs); keeps its tail when it may.
    /// `peaks` are the run's peaks so far: a ringing tail must not change them.
    pub fn check(&mut self, m: &Model, peaks: &Peaks, t: f64, y: &[f64]) -> bool {
        if !(t < m.t_end) {
            return false;
        }
        match self.tail_from(m, peaks, t, y) {
            Some(kind) => {
                self.tail = Some(Tail { t, kind });
                true
            }
            None => false,
        }
    }

    /// What is left of the run from `(t, y)`, if it is known in closed form.
    fn tail_from(&mut self, m: &Model, peaks: &Peaks, t: f64, y: &[f64]) -> Option<TailKind> {
        let stopped = m.robot.stopped();
        let ringing = |s: &mut Self| {
            s.stop
                .try_ringing_tail(m, peaks, t, y)
                .map(TailKind::Ringing)
        };
        if !((stopped || m.cruising_to_end()) && !m.regime.obj_contact) {
            return ringing(self);
        }
        let seg = *m.robot.current();
        // a cruising robot's run goes on while it may reach the object again (before the
        // impact, always): found from the state, without the physics. The tool that may end
        // here rides on with the robot, so the object must outrun the robot as well as the
        // tool's speed of the moment, which a tool at rest on its stop may have a little below
        // the robot's (by up to its rest tolerance)
        if !stopped {
            let v_r = seg.at(t).1;
            let v_t = m.layout.tool.map_or(v_r, |i| y[i + 1]);
            if !m.object_outruns(y, v_t.max(v_r)) {
                return ringing(self);
            }
        }
        // the physics at (t, y), computed once, and only where a test needs it: a tool still
        // bouncing on its stop under a standing robot fails the settling test on its speed
        // relative to the robot, `sd = v_r - v_t`, which the state gives as `Eval` does
        let physics = OnceCell::new();
        let e = || *physics.get_or_init(|| m.eval(t, y, &seg, &m.regime));
        let settled = match m.layout.tool {
            None if stopped => Some(TailKind::Settled),
            None => Some(TailKind::Riding { stroke: None }),
            Some(i) if stopped => (m.regime.tool_stuck
                || ((seg.at(t).1 - y[i + 1]).abs() <= self.settle_v
                    && e().a_t.abs() <= self.settle_a))
                .then_some(TailKind::Settled),
            // the robot cruises on: stuck (short of the sensor, or it would have switched; and
            // no compressible liquid still flowing through the orifice), or at rest on a stop
            Some(_) if m.regime.tool_stuck => m
                .layout
                .liquid
                .is_none()
                .then_some(TailKind::Riding { stroke: None }),
            Some(_) => self
                .stop
                .rest_on_stop(m, t, y, &seg, &e())
                .map(|s| TailKind::Riding { stroke: Some(s) }),
        };
        // (for a cruising robot, the object was found out of reach above)
        let object_done = || {
            !stopped
                || match m.layout.object {
                    None => true,
                    Some(_) if m.p.mu_n > 0.0 => m.regime.obj_stuck,
                    Some(_) => {
                        let e = e();
                        e.v_p >= e.v_t.max(0.0)
                    }
                }
        };
        match settled {
            Some(kind) if object_done() => Some(kind),
            _ => ringing(self),
        }
    }
}

impl Model {
    /// The object can never be touched again by a robot that cruises on: absent, or free (no
    /// plane friction) and not slower than `v` (m/s) in the state `y`.
    pub(crate) fn object_outruns(&self, y: &[f64], v: f64) -> bool {
        match self.layout.object {
            None => true,
            Some(j) => self.p.mu_n == 0.0 && y[j + 1] >= v.max(0.0),
        }
    }

    /// The robot cruises and will not brake before `t_end`: its sensor has not switched (it may
    /// yet), or the dead time ends after the run.
    pub(crate) fn cruising_to_end(&self) -> bool {
        self.robot.current().phase == Phase::Cruising
            && self.pending_brake.is_none_or(|tb| tb >= self.t_end)
    }
}
