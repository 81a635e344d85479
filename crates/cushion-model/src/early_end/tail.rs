//! The tail of a run: from its early end on, the state is known in closed form, and the run's
//! final values, its robot kinks and the trajectory's last samples come from it (`mod.rs`
//! decides when a run may end and which tail is left; the energy ledger over the tail:
//! `ledger.rs`).

use super::ringing_tail::RingingTail;
use crate::model::Model;
use crate::trajectory::EventLogEntry;

/// What is left of a run after its early end at `t`.
#[derive(Clone, Debug)]
pub(crate) struct Tail {
    /// When the run ended, s.
    pub t: f64,
    pub kind: TailKind,
}

/// How the state moves on from the early end (the object always flies on at its speed, or lies
/// stuck on the plane).
#[derive(Clone, Debug)]
pub(crate) enum TailKind {
    /// The robot stands and the tool has settled: it stays where it is.
    Settled,
    /// The robot cruises on to `t_end` and the tool rides with it: at rest on its stop at this
    /// stroke (m; `riding.rs`), or stuck where it is (`None`).
    Riding { stroke: Option<f64> },
    /// The tool rings on its stop, in closed form (`ringing_tail.rs`, `ringing_search.rs`); the robot may brake and
    /// stop on the way.
    Ringing(RingingTail),
}

impl Tail {
    /// The state at `t` from the state `y_te` at the early end: the object in free flight (or
    /// at rest), the tool as its kind says; the ledger's states as at the early end.
    pub fn state_at(&self, m: &Model, y_te: &[f64], t: f64) -> Vec<f64> {
        let te = self.t;
        let mut y = y_te.to_vec();
        let l = m.layout;
        if let Some(j) = l.object {
            if !(m.p.mu_n > 0.0 && m.regime.obj_stuck) {
                y[j] += y[j + 1] * (t - te);
            }
        }
        let Some(i) = l.tool else {
            return y;
        };
        let (x_r, v_r, _) = m.robot.segment_at(t).at(t);
        match &self.kind {
            TailKind::Ringing(tail) => {
                let (s, sd) = tail.stroke_at(t);
                y[i] = x_r - s;
                y[i + 1] = v_r - sd;
            }
            TailKind::Riding { stroke: Some(s_eq) } => {
                y[i] = x_r - s_eq;
                y[i + 1] = v_r;
            }
            TailKind::Riding { stroke: None } => y[i] += x_r - m.robot.segment_at(te).at(te).0,
            TailKind::Settled => {}
        }
        y
    }

    /// When the robot begins to brake and when it stands, if that happens inside the tail.
    pub fn robot_kinks(&self) -> (Option<f64>, Option<f64>) {
        match &self.kind {
            TailKind::Ringing(r) => (r.brake, r.stop),
            _ => (None, None),
        }
    }

    /// Play the tail to `t_end` on the model: the robot's kinks inside it go into its profile
    /// and the event log (with the state there), and so does the early end itself. Returns the
    /// state at `t_end`.
    pub fn play(&self, m: &mut Model, y_te: &[f64], t_end: f64) -> Vec<f64> {
        let te = self.t;
        let (brake, stop) = self.robot_kinks();
        if let Some(tb) = brake {
            m.robot.brake(tb);
            self.log(m, "brake", y_te, tb);
        }
        if let Some(ts) = stop {
            self.stop_robot(m, y_te, ts);
        }
        let y = self.state_at(m, y_te, t_end);
        let point = m.point_at(te, y_te);
        m.log.push(EventLogEntry {
            t: te,
            name: "early_end".into(),
            point,
        });
        y
    }

    /// Where the run is integrated again after this tail (`RingingTail::resume`: the robot's
    /// stop); `None` for a tail that ends the run.
    pub fn resume_time(&self) -> Option<f64> {
        match &self.kind {
            TailKind::Ringing(r) => r.resume,
            _ => None,
        }
    }

    /// Where the integration resumes after a tail that ends before the run does, and the state
    /// there; `None` for a tail that ends the run. The robot's stop goes into its profile and
    /// the event log, as the integrated run's time stop puts it there.
    pub fn resume(&self, m: &mut Model, y_te: &[f64]) -> Option<(f64, Vec<f64>)> {
        let ts = self.resume_time()?;
        self.stop_robot(m, y_te, ts);
        Some((ts, self.state_at(m, y_te, ts)))
    }

    /// The robot stands at `ts`, inside the tail or where it ends: into its profile and the
    /// event log, with the tail's state there.
    fn stop_robot(&self, m: &mut Model, y_te: &[f64], ts: f64) {
        m.robot.on_time(ts);
        self.log(m, "robot_stopped", y_te, ts);
    }

    /// The ringing's sample spacing for a trajectory without uniform samples: 16 points per
    /// period (`None` for the other kinds, whose tail is a straight line).
    pub fn ringing_spacing(&self) -> Option<f64> {
        let TailKind::Ringing(r) = &self.kind else {
            return None;
        };
        let w0 = r.pieces.last().map_or(1.0, |p| p.ring.w0);
        Some(2.0 * std::f64::consts::PI / w0 / 16.0)
    }

    /// Log the event `name` at `t`, with the state there.
    fn log(&self, m: &mut Model, name: &str, y_te: &[f64], t: f64) {
        let point = m.point_at(t, &self.state_at(m, y_te, t));
        m.log.push(EventLogEntry {
            t,
            name: name.into(),
            point,
        });
    }
}
