//! OREGO: the Oregonator, Field and Noyes' model of the Belousov–Zhabotinskii reaction, three
//! equations, stiff, periodic with steep fronts, on `[0, 360]`. Hairer & Wanner, *Solving ODEs
//! II*, Sec. IV.10; Test Set for IVP Solvers (F. Mazzia, C. Magherini, University of Bari),
//! problem OREGO, whose reference solution at the end ([`REFERENCE`]) was computed with
//! RADAU in quadruple precision.

use crate::{Matrix, OdeSystem, State};

/// End of the interval.
pub const T_END: f64 = 360.0;

/// The reference solution at [`T_END`] (Test Set for IVP Solvers, `orego`).
#[allow(clippy::excessive_precision)]
pub const REFERENCE: [f64; 3] = [
    0.100_081_487_031_852_3e1,
    0.122_817_852_154_991_7e4,
    0.132_055_494_284_670_6e3,
];

/// The initial state.
pub fn initial_state() -> State<3> {
    State::<3>::new(1.0, 2.0, 3.0)
}

const S: f64 = 77.27;
const W: f64 = 0.161;
const Q: f64 = 8.375e-6;

pub struct Orego;

impl OdeSystem<3> for Orego {
    fn rhs(&self, _t: f64, y: &State<3>) -> State<3> {
        State::<3>::new(
            S * (y[1] + y[0] * (1.0 - Q * y[0] - y[1])),
            (y[2] - (1.0 + y[0]) * y[1]) / S,
            W * (y[0] - y[2]),
        )
    }

    fn jacobian(&self, _t: f64, y: &State<3>) -> Option<Matrix<3>> {
        Some(Matrix::<3>::new(
            S * (1.0 - 2.0 * Q * y[0] - y[1]),
            S * (1.0 - y[0]),
            0.0,
            -y[1] / S,
            -(1.0 + y[0]) / S,
            1.0 / S,
            W,
            0.0,
            -W,
        ))
    }

    fn time_derivative(&self, _t: f64, _y: &State<3>) -> Option<State<3>> {
        Some(State::<3>::zeros())
    }
}
