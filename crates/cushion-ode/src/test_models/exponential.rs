//! `y' = lambda * y` for a 2-vector with different rates; `y(t) = y0 * exp(lambda t)`.

use crate::{OdeSystem, State};

/// Two independent decays (or growths) with rates `lambda`.
pub struct Exponential {
    pub lambda: [f64; 2],
}

impl Exponential {
    pub fn exact(&self, t: f64, y0: &State<2>) -> State<2> {
        State::<2>::new(
            y0[0] * (self.lambda[0] * t).exp(),
            y0[1] * (self.lambda[1] * t).exp(),
        )
    }
}

impl OdeSystem<2> for Exponential {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(self.lambda[0] * y[0], self.lambda[1] * y[1])
    }
}

/// A harmonic oscillator `x'' = -x` written as `(x, v)`: `x = cos t`, `v = -sin t`.
pub struct Oscillator;

impl OdeSystem<2> for Oscillator {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], -y[0])
    }
}
