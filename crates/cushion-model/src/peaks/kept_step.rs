//! A step kept while the sample at its end may be a top: the next step's first sample decides,
//! and the peak may then lie on either side of the step's end, so the search needs this step's
//! dense output as well as the next one's.

use crate::model::{Eval, Model, Regime, MAX_STATES};
use crate::physics::Segment;
use cushion_ode::{DenseOutput, State};

/// The most states the physics reads (tool 2 + liquid 2 + object 2; they come first in the
/// layout): the ledger's quadratures after them do not enter any force.
pub(crate) const MAX_DYNAMIC: usize = 6;

/// A step kept while the sample at its end may be a top: its dense output (the states the
/// physics reads, [`DenseOutput::leading`]), with the robot segment and regime it ran in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KeptStep {
    pub dense: DenseOutput<MAX_DYNAMIC>,
    pub seg: Segment,
    pub regime: Regime,
    /// Whether its dense output is stable (`cushion_ode::Step::dense_stable`).
    pub dense_stable: bool,
}

impl KeptStep {
    /// The states the physics reads at the step's start.
    pub fn start(&self) -> State<MAX_DYNAMIC> {
        self.dense.eval(self.dense.t0)
    }

    /// The physics at `t` on the step's dense output, in the segment and regime the step ran
    /// in (the quadratures after the kept states, which no force reads, are zero).
    pub fn eval(&self, model: &Model, t: f64) -> Eval {
        let mut y = [0.0; MAX_STATES];
        y[..MAX_DYNAMIC].copy_from_slice(self.dense.eval(t).as_slice());
        let n = model.layout.n.clamp(1, MAX_STATES);
        model.eval(t, &y[..n], &self.seg, &self.regime)
    }
}
