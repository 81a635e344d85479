//! What observes a run, apart from the physics it observes: each observer sees every accepted
//! step and every event, and none of them changes the solution.
//!
//! - `peaks/`: the peaks of `|F_r|`, `F_c`, the stroke and the gas pressure;
//! - `early_end/`: the early end, which stops the run once what is left of it is known in
//!   closed form (`early_end/tail.rs`); off with `solver.early_end = false`. It reads the peaks
//!   so far, so it watches behind the peak sampler (`early_end/watch.rs`);
//! - `observe/recorder.rs`: the trajectory, when one is asked for.
//!
//! Each is an observer of the integrator (`cushion_ode::Observer`) in its own file, and
//! [`Watchers`] is them as one, a nested pair, beside the model, which answers every question
//! about the system (right-hand side, Jacobian, event functions and handlers): OrdinaryDiffEq's
//! `CallbackSet` beside its problem. A new observer is a file that implements
//! `cushion_ode::Observer<Model, N>`, a field of [`Observed`] and its place in [`Watchers`].

pub(crate) mod recorder;

use crate::early_end::{EarlyEnd, PeaksThenEarlyEnd};
use crate::model::Model;
use crate::peaks::PeakSampler;
use recorder::Recorder;

/// The model with its observers: what a run keeps.
pub(crate) struct Observed {
    pub model: Model,
    pub peaks: PeakSampler,
    pub early_end: Option<EarlyEnd>,
    pub recorder: Option<Recorder>,
}

/// The observers of one solve, in the order each hook reaches them.
pub(crate) type Watchers<'a> = (Option<&'a mut Recorder>, PeaksThenEarlyEnd<'a>);

impl Observed {
    /// The model and, apart, its observers, for `cushion_ode::solve_observed`.
    pub(crate) fn split(&mut self) -> (&mut Model, Watchers<'_>) {
        let peaks = PeaksThenEarlyEnd {
            peaks: &mut self.peaks,
            early_end: self.early_end.as_mut(),
        };
        (&mut self.model, (self.recorder.as_mut(), peaks))
    }
}
