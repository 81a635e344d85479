//! The early end (`solver.early_end`): a run ends once nothing a summary reports can change any
//! more, and what is left of it is known in closed form, its [`Tail`]. [`EarlyEnd::check`] is
//! the one entry point: its observer (`watch.rs`, behind the peak sampler) asks it at every
//! step and robot kink whether the run may end there, and it keeps the tail when it may. The
//! tail then gives the final state at `t_end`, the robot's kinks, the energy ledger's terms and
//! the trajectory's last samples.
//!
//! Which tail is left, the first that applies:
//! - **settled** (`settled.rs`): the robot stands, the tool has settled, the object is done
//!   (out of contact, and free and not slower than the tool, or stuck on the plane);
//! - **riding** (`riding.rs`): the robot cruises on with no brake before `t_end`, the object
//!   outruns it, and the tool rides with it, stuck or at rest on its stop;
//! - **ringing** (`ringing_search.rs`, `solver.ringing_tail`): only the tool's small ringing on
//!   its stop is left, written as an averaged weakly nonlinear oscillator (`ringing.rs`) about
//!   its equilibrium on the stop (`linearisation.rs`) for each robot segment to come
//!   (`ringing_tail.rs`); it may end at the robot's stop, where the run is integrated again.
//!
//! Files: `tail.rs` the tail played to `t_end`; `ledger.rs` the energy ledger over a ringing
//! tail. The tool's equilibria on its stop are computed once per robot acceleration and holding
//! stop and shared by the riding and the ringing tails ([`Linearisations`]): which equilibrium
//! was found first (Newton's start) sets the last bits of later tails.
//!
//! What the early end asks of the model is either physics, which lives in `model/` with the
//! rest of the force law (`Model::tool_force`, `Model::holding_depth`), or a question only the
//! early end asks of the model's state (whether the object can be touched again, whether the
//! robot cruises to `t_end`), which lives here as a function of the model: nothing outside
//! `model/` implements `Model`.

mod ledger;
mod linearisation;
mod riding;
mod ringing;
mod ringing_search;
mod ringing_tail;
mod settled;
mod tail;
mod watch;

pub(crate) use ledger::add_to_ledger;
pub(crate) use tail::Tail;
pub(crate) use watch::PeaksThenEarlyEnd;

use crate::model::Model;
use crate::peaks::Peaks;
use crate::physics::Phase;
use crate::Scene;
use linearisation::Linearisations;
use riding::Riding;
use ringing_search::RingingSearch;
use settled::Settled;
use tail::TailKind;

/// The early-end observer (`solver.early_end`), with the ringing tail's search
/// (`solver.ringing_tail`).
pub(crate) struct EarlyEnd {
    settled: Settled,
    riding: Riding,
    ringing: RingingSearch,
    /// The tool's equilibria on its stop, kept: the riding and the ringing tails share them.
    linearisations: Linearisations,
    /// The run's tail, once it has ended early.
    pub tail: Option<Tail>,
}

impl EarlyEnd {
    pub fn new(scene: &Scene) -> EarlyEnd {
        EarlyEnd {
            settled: Settled::new(scene),
            riding: Riding::new(scene),
            ringing: RingingSearch::new(scene),
            linearisations: Linearisations::default(),
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

    /// What is left of the run from `(t, y)`, if it is known in closed form: the settled tail
    /// under a standing robot, the riding tail under one that cruises on, else the ringing.
    fn tail_from(&mut self, m: &Model, peaks: &Peaks, t: f64, y: &[f64]) -> Option<TailKind> {
        let lins = &mut self.linearisations;
        let still = if m.robot.stopped() {
            self.settled.tail(m, t, y)
        } else {
            self.riding.tail(lins, m, t, y)
        };
        still.or_else(|| {
            self.ringing
                .try_tail(lins, m, peaks, t, y)
                .map(TailKind::Ringing)
        })
    }
}

/// The object can never be touched again by a robot that cruises on: absent, or free (no
/// plane friction) and not slower than `v` (m/s) in the state `y`.
fn object_outruns(m: &Model, y: &[f64], v: f64) -> bool {
    match m.layout.object {
        None => true,
        Some(j) => m.p.mu_n == 0.0 && y[j + 1] >= v.max(0.0),
    }
}

/// The robot cruises and will not brake before `t_end`: its sensor has not switched (it may
/// yet), or the dead time ends after the run.
fn cruising_to_end(m: &Model) -> bool {
    m.robot.current().phase == Phase::Cruising && m.pending_brake.is_none_or(|tb| tb >= m.t_end)
}
