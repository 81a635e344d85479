//! Robertson's chemical kinetics (Hairer–Wanner II, the classic stiff test): three species,
//! rate constants spanning nine orders of magnitude, integrated to `t = 1e11`. Reference
//! solution at the end ([`REFERENCE_1E11`]) from the Test Set for IVP Solvers (F. Mazzia,
//! C. Magherini, University of Bari), problem ROBER.

use crate::{Matrix, OdeSystem, State};

/// End of the Test Set's interval.
pub const T_END: f64 = 1e11;

/// The reference solution at [`T_END`] from `y(0) = (1, 0, 0)` (Test Set for IVP Solvers,
/// `rober`).
#[allow(clippy::excessive_precision)]
pub const REFERENCE_1E11: [f64; 3] = [
    0.208_334_014_970_125_5e-7,
    0.833_336_077_033_471_3e-13,
    0.999_999_979_166_505_0,
];

pub struct Robertson;

impl OdeSystem<3> for Robertson {
    fn rhs(&self, _t: f64, y: &State<3>) -> State<3> {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        State::<3>::new(-r1 + r2, r1 - r2 - r3, r3)
    }

    fn jacobian(&self, _t: f64, y: &State<3>) -> Option<Matrix<3>> {
        Some(Matrix::<3>::new(
            -0.04,
            1e4 * y[2],
            1e4 * y[1],
            0.04,
            -1e4 * y[2] - 6e7 * y[1],
            -1e4 * y[1],
            0.0,
            6e7 * y[1],
            0.0,
        ))
    }

    fn time_derivative(&self, _t: f64, _y: &State<3>) -> Option<State<3>> {
        Some(State::<3>::zeros())
    }
}
