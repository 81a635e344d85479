//! The early end: when nothing can change any more, the run stops and its final values are
//! extrapolated exactly (or the tool's small ringing is written in closed form,
//! `ringing_tail.rs`).

use super::Model;
use crate::physics::Phase;

impl Model {
    /// Whether nothing can change any more after `(t, y)`: the robot stands, or cruises with no
    /// brake before `t_end` (its sensor never switched, or the dead time ends after the run); the
    /// tool has settled (robot standing: stuck, or relative speed and acceleration at the
    /// tolerance's level; robot cruising: stuck short of the sensor, or at rest on its stop,
    /// `resting.rs`); and the object is out of contact and either free and not slower than the
    /// tool (nor, while the robot cruises, than the robot, which the resting tool rides with) or,
    /// with the robot standing, stuck on the plane. Then the run may end early
    /// with its final values extrapolated exactly. Failing that, the run may still end if only
    /// the tool's small ringing on its stop is left, written in closed form
    /// (`ringing_tail.rs`).
    pub(crate) fn can_end_early(&mut self, t: f64, y: &[f64]) -> bool {
        let stopped = self.robot.stopped();
        if !(self.early_end_enabled
            && t < self.t_end
            && (stopped || self.cruising_to_end())
            && !self.regime.obj_contact)
        {
            return t < self.t_end && self.try_ringing_tail(t, y);
        }
        let seg = *self.robot.current();
        // a cruising robot's run goes on while it may reach the object again (before the
        // impact, always): found from the state, without the physics. The tool that may end
        // here rides on with the robot, so the object must outrun the robot as well as the
        // tool's speed of the moment, which a tool at rest on its stop may have a little below
        // the robot's (by up to its rest tolerance)
        if !stopped {
            let v_r = seg.at(t).1;
            let v_t = self.layout.tool.map_or(v_r, |i| y[i + 1]);
            if !self.object_outruns(y, v_t.max(v_r)) {
                return self.try_ringing_tail(t, y);
            }
        }
        let e = self.eval(t, y, &seg, &self.regime);
        // (for a cruising robot, the object was found out of reach above)
        let object_done = !stopped
            || match self.layout.object {
                None => true,
                Some(_) => {
                    if self.p.mu_n > 0.0 {
                        self.regime.obj_stuck
                    } else {
                        e.v_p >= e.v_t.max(0.0)
                    }
                }
            };
        let tool_settled = match self.layout.tool {
            None => true,
            Some(_) if stopped => {
                self.regime.tool_stuck
                    || (e.sd.abs() <= self.settle_v && e.a_t.abs() <= self.settle_a)
            }
            // the robot cruises on: stuck (short of the sensor, or it would have switched; and
            // no compressible liquid still flowing through the orifice), or at rest on a stop
            Some(_) if self.regime.tool_stuck => self.layout.liquid.is_none(),
            Some(_) => {
                self.rest_stroke = self.rest_on_stop(t, y, &seg, &e);
                self.rest_stroke.is_some()
            }
        };
        (tool_settled && object_done) || self.try_ringing_tail(t, y)
    }

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
