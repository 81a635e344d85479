//! Van der Pol's oscillator `x'' = mu ((1 - x^2) x' - x)`, in Hairer's scaled form
//! (`y1' = y2`, `y2' = ((1 - y1^2) y2 - y1) / eps` with `eps = 1 / mu`); stiff for large `mu`.
//! With `eps = 1e-6`, `y(0) = (2, 0)` on `[0, 2]` it is problem VDPOL of the Test Set for IVP
//! Solvers (F. Mazzia, C. Magherini, University of Bari), whose reference solution at `t = 2`
//! is [`REFERENCE_EPS_1E6`].

use crate::{Matrix, OdeSystem, State};

/// The reference solution at `t = 2` for `mu = 1e6` from `y(0) = (2, 0)` (Test Set for IVP
/// Solvers, `vdpol`, computed with RADAU in quadruple precision).
#[allow(clippy::excessive_precision)]
pub const REFERENCE_EPS_1E6: [f64; 2] = [0.170_616_773_217_048_3e1, -0.892_809_701_024_797_5];

pub struct VanDerPol {
    pub mu: f64,
}

impl OdeSystem<2> for VanDerPol {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], self.mu * ((1.0 - y[0] * y[0]) * y[1] - y[0]))
    }

    fn jacobian(&self, _t: f64, y: &State<2>) -> Option<Matrix<2>> {
        Some(Matrix::<2>::new(
            0.0,
            1.0,
            self.mu * (-2.0 * y[0] * y[1] - 1.0),
            self.mu * (1.0 - y[0] * y[0]),
        ))
    }

    fn time_derivative(&self, _t: f64, _y: &State<2>) -> Option<State<2>> {
        Some(State::<2>::zeros())
    }
}
