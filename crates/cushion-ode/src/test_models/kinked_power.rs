//! A harmonic oscillator and the work of a quadratic damper on it, `x' = v`, `v' = -x`,
//! `z' = v |v|` (the damper does not act back): `z'` has a jump in its second derivative
//! wherever `v` changes sign, as an orifice's pressure drop does where the tool turns.
//! `x = cos t`, `v = -sin t`, and `z` in closed form: on `[k pi, (k + 1) pi]`,
//! `v |v| = -(-1)^k sin^2 t`, whose integral is `t / 2 - sin(2 t) / 4`.

use crate::{OdeSystem, State};
use std::f64::consts::PI;

/// The problem; `kinks`: whether it names `v` as its kink function
/// ([`OdeSystem::kink_count`]).
pub struct KinkedPower {
    pub kinks: bool,
}

impl KinkedPower {
    /// `(x, v, z)` at `t >= 0` from `(1, 0, 0)` at 0.
    pub fn exact(t: f64) -> State<3> {
        let k = (t / PI).floor();
        // the whole half periods before: each contributes -(-1)^j pi / 2
        let whole = if k as i64 % 2 == 1 { -PI / 2.0 } else { 0.0 };
        let sign = if k as i64 % 2 == 1 { 1.0 } else { -1.0 };
        let part = (t - k * PI) / 2.0 - (2.0 * t).sin() / 4.0;
        State::<3>::new(t.cos(), -t.sin(), whole + sign * part)
    }
}

impl OdeSystem<3> for KinkedPower {
    fn rhs(&self, _t: f64, y: &State<3>) -> State<3> {
        State::<3>::new(y[1], -y[0], y[1] * y[1].abs())
    }

    fn kink_count(&self) -> usize {
        usize::from(self.kinks)
    }

    fn kink(&self, _i: usize, _t: f64, y: &State<3>) -> f64 {
        y[1]
    }
}
