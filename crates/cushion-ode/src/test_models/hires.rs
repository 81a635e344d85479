//! HIRES: "High Irradiance RESponse", the growth of plant tissue under light (Schäfer 1975),
//! eight linear-plus-one-quadratic kinetic equations, mildly stiff, on `[0, 321.8122]`.
//! Hairer & Wanner, *Solving ODEs II*, Sec. IV.10; Test Set for IVP Solvers (F. Mazzia,
//! C. Magherini, University of Bari), problem HIRES, whose reference solution at the end
//! ([`REFERENCE`]) was computed with RADAU5 in quadruple precision.

use crate::{Matrix, OdeSystem, State};

/// End of the interval.
pub const T_END: f64 = 321.8122;

/// The reference solution at [`T_END`] (Test Set for IVP Solvers, `hires`).
#[allow(clippy::excessive_precision)]
pub const REFERENCE: [f64; 8] = [
    0.737_131_257_332_566_8e-3,
    0.144_248_572_631_618_5e-3,
    0.588_872_974_096_757_5e-4,
    0.117_565_134_328_314_9e-2,
    0.238_635_619_883_133_1e-2,
    0.623_896_825_274_279_6e-2,
    0.284_999_839_518_576_9e-2,
    0.285_000_160_481_423_1e-2,
];

/// The initial state.
pub fn initial_state() -> State<8> {
    State::<8>::from([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057])
}

pub struct Hires;

impl OdeSystem<8> for Hires {
    fn rhs(&self, _t: f64, y: &State<8>) -> State<8> {
        let r = 280.0 * y[5] * y[7];
        State::<8>::from([
            -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
            1.71 * y[0] - 8.75 * y[1],
            -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4],
            8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3],
            -1.745 * y[4] + 0.43 * y[5] + 0.43 * y[6],
            -r + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6],
            r - 1.81 * y[6],
            -r + 1.81 * y[6],
        ])
    }

    fn jacobian(&self, _t: f64, y: &State<8>) -> Option<Matrix<8>> {
        let mut j = Matrix::<8>::zeros();
        j[(0, 0)] = -1.71;
        j[(0, 1)] = 0.43;
        j[(0, 2)] = 8.32;
        j[(1, 0)] = 1.71;
        j[(1, 1)] = -8.75;
        j[(2, 2)] = -10.03;
        j[(2, 3)] = 0.43;
        j[(2, 4)] = 0.035;
        j[(3, 1)] = 8.32;
        j[(3, 2)] = 1.71;
        j[(3, 3)] = -1.12;
        j[(4, 4)] = -1.745;
        j[(4, 5)] = 0.43;
        j[(4, 6)] = 0.43;
        j[(5, 3)] = 0.69;
        j[(5, 4)] = 1.71;
        j[(5, 5)] = -0.43 - 280.0 * y[7];
        j[(5, 6)] = 0.69;
        j[(5, 7)] = -280.0 * y[5];
        j[(6, 5)] = 280.0 * y[7];
        j[(6, 6)] = -1.81;
        j[(6, 7)] = 280.0 * y[5];
        j[(7, 5)] = -280.0 * y[7];
        j[(7, 6)] = 1.81;
        j[(7, 7)] = -280.0 * y[5];
        Some(j)
    }

    fn time_derivative(&self, _t: f64, _y: &State<8>) -> Option<State<8>> {
        Some(State::<8>::zeros())
    }
}
