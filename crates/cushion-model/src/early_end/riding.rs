//! The riding tail: the robot cruises on to `t_end` with no brake before it (its sensor never
//! switches, or the dead time ends after the run), the object is absent or outruns the robot,
//! and the tool rides with the robot: stuck by dry friction (short of the sensor, or it would
//! have switched), or at rest on a stop. Nothing can change any more.
//!
//! Rest on a stop: a tool pressed onto its stop by a strong preload is overdamped there (the
//! stop's Hunt–Crossley damping `chi d^1.5` grows with the depth): DOPRI5 then steps at its
//! stability limit, and its solution keeps a wobble of the tolerance's size in the tool's speed
//! (about `rtol v_r`: 1e-6 m/s at 1 m/s). The speed test of the standing robot's settled tail
//! (`100 atol`, `settled.rs`) never passes on it, so without the test below such runs would
//! integrate the resting tool to `t_end`
//! (`tests/model/early_end.rs::early_end_while_the_robot_cruises_on`).
//!
//! Here the tool is at rest when its deviation from the equilibrium on its stop, as the speed
//! `hypot(sd, w0 u)` (`u = s - s_eq`; the largest speed its energy allows in the linearised
//! oscillator, whose energy only decreases), is within 10 times the speed tolerance
//! `atol + rtol |v_r|`, and when the oscillator's slowest mode decays by a factor of 1000 before
//! `t_end` (rate `zeta w0` below critical damping, `w0 (zeta - sqrt(zeta^2 - 1))` above it). The
//! tool is then, at `t_end`, at the equilibrium to a small fraction of the speed tolerance,
//! riding with the robot: the extrapolation puts it there (`x_t = x_r - s_eq`, `v_t = v_r`).

use super::linearisation::Linearisations;
use super::tail::TailKind;
use super::{cruising_to_end, object_outruns};
use crate::model::{Eval, Model};
use crate::physics::Segment;
use crate::Scene;

/// How much the tool's deviation from rest must decay before `t_end`.
const DECAY_BEFORE_END: f64 = 1000.0;

/// Largest deviation from rest, as a multiple of the speed tolerance `atol + rtol |v_r|`.
const REST_SPEED: f64 = 10.0;

/// The riding tail's test: the solver's tolerances, which say when the tool is at rest.
pub(super) struct Riding {
    atol: f64,
    rtol: f64,
}

impl Riding {
    pub fn new(scene: &Scene) -> Riding {
        Riding {
            atol: scene.solver.atol,
            rtol: scene.solver.rtol,
        }
    }

    /// The riding tail from `(t, y)`, if the robot cruises on to `t_end`, the object is out of
    /// contact and outruns it, and the tool rides with it (see the module docs); `lins` are the
    /// tool's equilibria on its stop, kept.
    pub fn tail(
        &self,
        lins: &mut Linearisations,
        m: &Model,
        t: f64,
        y: &[f64],
    ) -> Option<TailKind> {
        if m.regime.obj_contact || !cruising_to_end(m) {
            return None;
        }
        let seg = *m.robot.current();
        // the run goes on while the robot may reach the object again (before the impact,
        // always): found from the state, without the physics. The tool that may end here rides
        // on with the robot, so the object must outrun the robot as well as the tool's speed
        // of the moment, which a tool at rest on its stop may have a little below the robot's
        // (by up to its rest tolerance)
        let v_r = seg.at(t).1;
        let v_t = m.layout.tool.map_or(v_r, |i| y[i + 1]);
        if !object_outruns(m, y, v_t.max(v_r)) {
            return None;
        }
        match m.layout.tool {
            None => Some(TailKind::Riding { stroke: None }),
            // stuck (short of the sensor, or it would have switched; and no compressible liquid
            // still flowing through the orifice), or at rest on a stop
            Some(_) if m.regime.tool_stuck => m
                .layout
                .liquid
                .is_none()
                .then_some(TailKind::Riding { stroke: None }),
            Some(_) => {
                let e = m.eval(t, y, &seg, &m.regime);
                self.rest_on_stop(lins, m, t, y, &seg, &e)
                    .map(|s| TailKind::Riding { stroke: Some(s) })
            }
        }
    }

    /// The equilibrium stroke (m) of a tool that has come to rest on its stop, if it has (see
    /// the module docs); `e` is the physics at `(t, y)` on the robot segment `seg`. It must also
    /// stay short of the sensor, if that has not switched yet.
    fn rest_on_stop(
        &self,
        lins: &mut Linearisations,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        e: &Eval,
    ) -> Option<f64> {
        let r = &m.regime;
        let tol_v = self.atol + self.rtol * e.v_r.abs();
        // cheap tests first: one stop holds the tool, no friction or liquid state that could
        // move it on, and its speed is at the level of the tolerance
        if m.layout.liquid.is_some()
            || r.cavitating
            || r.fwd == r.back
            || m.p.d > 0.0
            || !(e.sd.abs() <= REST_SPEED * tol_v)
        {
            return None;
        }
        let lin = lins.linearisation(m, t, y, seg, seg.a, e.s)?;
        let c = &lin.coef;
        if !(c.k1 > 0.0 && c.c > 0.0) {
            return None;
        }
        let w0 = c.w0();
        let zeta = c.linear_decay() / w0;
        let rate = if zeta < 1.0 {
            zeta * w0
        } else {
            w0 * (zeta - (zeta * zeta - 1.0).sqrt())
        };
        let speed = e.sd.hypot(w0 * (e.s - lin.s_eq));
        let sensor_quiet = m.regime.detected || lin.s_eq + 2.0 * speed / w0 < m.p.s_sensor;
        (speed <= REST_SPEED * tol_v
            && rate * (m.t_end - t) >= DECAY_BEFORE_END.ln()
            && sensor_quiet)
            .then_some(lin.s_eq)
    }
}

#[cfg(test)]
mod tests {
    use crate::early_end::EarlyEnd;
    use crate::model::Model;
    use crate::peaks::PeakSampler;
    use crate::Scene;

    /// The default scene at `t = 0`: the robot cruises at 1 m/s and its sensor has not switched,
    /// the tool sits at its preload equilibrium on the forward stop, the object lies free just
    /// ahead. The tool's speed is set `dv_t` below the robot's (within the rest tolerance of
    /// `10 (atol + rtol v_r)` = 1e-5 m/s, so the tool counts as at rest), the object's `dv_p`
    /// below. Returns whether the run may end there.
    fn may_end(dv_t: f64, dv_p: f64) -> bool {
        let scene = Scene::default();
        let model = Model::new(&scene);
        let mut early_end = EarlyEnd::new(&scene);
        let peaks = PeakSampler::new(&model, scene.solver.rtol).peaks;
        let mut y = model.y0.clone();
        let (i, j) = (model.layout.tool.unwrap(), model.layout.object.unwrap());
        let v_r = scene.robot.approach_speed;
        y[i + 1] = v_r - dv_t;
        y[j + 1] = v_r - dv_p;
        early_end.check(&model, &peaks, 0.0, &y)
    }

    #[test]
    fn an_object_faster_than_the_robot_lets_the_resting_tool_end_the_run() {
        assert!(may_end(4e-6, -1e-3));
        assert!(may_end(0.0, 0.0));
    }

    #[test]
    fn an_object_slower_than_the_cruising_robot_does_not() {
        // The object is faster than the tool of the moment but slower than the robot: the
        // resting tool rides on with the robot and reaches the object again, so an early end
        // here would extrapolate the object through the tool by `t_end` (and the energy ledger
        // would no longer close).
        assert!(!may_end(4e-6, 2e-6));
        assert!(!may_end(0.0, 1e-9));
    }
}
