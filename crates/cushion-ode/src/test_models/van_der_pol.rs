//! Van der Pol's oscillator `x'' = mu ((1 - x^2) x' - x)`, in Hairer's form; stiff for large `mu`.

use crate::{OdeSystem, State};

pub struct VanDerPol {
    pub mu: f64,
}

impl OdeSystem<2> for VanDerPol {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], self.mu * ((1.0 - y[0] * y[0]) * y[1] - y[0]))
    }
}
