//! The Arenstorf orbit (Hairer, Nørsett, Wanner I, eq. II.0.1): a periodic orbit of the
//! restricted three-body problem, period `T = 17.0652165601579625588917206249`.

use crate::{OdeSystem, State};

/// Moon's mass ratio.
pub const MU: f64 = 0.012277471;
/// The orbit's period.
pub const PERIOD: f64 = 17.065_216_560_157_962_558_891_720_624_9;

/// The initial state `(y1, y2, y1', y2')`.
#[allow(clippy::excessive_precision)] // the digits as Hairer publishes them
pub fn initial_state() -> State<4> {
    State::<4>::new(0.994, 0.0, 0.0, -2.001_585_106_379_082_522_420_537_862_224)
}

pub struct Arenstorf;

impl OdeSystem<4> for Arenstorf {
    #[inline]
    fn rhs(&self, _t: f64, y: &State<4>) -> State<4> {
        let mu = MU;
        let mup = 1.0 - mu;
        let r1 = (y[0] + mu).powi(2) + y[1] * y[1];
        let r2 = (y[0] - mup).powi(2) + y[1] * y[1];
        let (d1, d2) = (r1 * r1.sqrt(), r2 * r2.sqrt());
        State::<4>::new(
            y[2],
            y[3],
            y[0] + 2.0 * y[3] - mup * (y[0] + mu) / d1 - mu * (y[0] - mup) / d2,
            y[1] - 2.0 * y[2] - mup * y[1] / d1 - mu * y[1] / d2,
        )
    }
}
