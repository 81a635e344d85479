//! A nonlinear, non-autonomous system with a known solution, for measuring orders: with
//! `phi(t) = (cos t, sin 2t)` and `F(y) = (-y1^3 + y1 y2, -y1 - 2 y2 + y2^2)`,
//! `y' = phi'(t) + F(y) - F(phi(t))` has the solution `y = phi` from `y(0) = phi(0)` (the
//! manufactured-solution idea of Prothero and Robinson's test equation). Its Jacobian is
//! `F'(y)` and its `df/dt` is `phi'' - F'(phi) phi'`, both given: a finite-difference `df/dt`
//! (error ~ `sqrt(eps)`) would put a floor of about 1e-12 under the error of a step.

use crate::{Matrix, OdeSystem, State};

pub struct Manufactured;

impl Manufactured {
    /// The exact solution `phi(t)`.
    pub fn exact(t: f64) -> State<2> {
        State::<2>::new(t.cos(), (2.0 * t).sin())
    }

    fn force(y: &State<2>) -> State<2> {
        State::<2>::new(
            -y[0] * y[0] * y[0] + y[0] * y[1],
            -y[0] - 2.0 * y[1] + y[1] * y[1],
        )
    }
}

impl OdeSystem<2> for Manufactured {
    fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
        let dphi = State::<2>::new(-t.sin(), 2.0 * (2.0 * t).cos());
        dphi + Self::force(y) - Self::force(&Self::exact(t))
    }

    fn jacobian(&self, _t: f64, y: &State<2>) -> Option<Matrix<2>> {
        Some(Matrix::<2>::new(
            -3.0 * y[0] * y[0] + y[1],
            y[0],
            -1.0,
            -2.0 + 2.0 * y[1],
        ))
    }

    fn time_derivative(&self, t: f64, _y: &State<2>) -> Option<State<2>> {
        let phi = Self::exact(t);
        let dphi = State::<2>::new(-t.sin(), 2.0 * (2.0 * t).cos());
        let ddphi = State::<2>::new(-t.cos(), -4.0 * (2.0 * t).sin());
        Some(ddphi - self.jacobian(t, &phi)? * dphi)
    }
}
