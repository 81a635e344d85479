//! Robertson's chemical kinetics (Hairer–Wanner II, the classic stiff test).

use crate::{OdeSystem, State};

pub struct Robertson;

impl OdeSystem<3> for Robertson {
    fn rhs(&self, _t: f64, y: &State<3>) -> State<3> {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        State::<3>::new(-r1 + r2, r1 - r2 - r3, r3)
    }
}
