//! A problem that is stiff at first and not later, with a closed-form solution: `y' =
//! -lambda(t) (y - sin t) + cos t`, `lambda(t) = lambda0 exp(-decay t)`, `y(0) = 0`, whose
//! solution is `y = sin t` whatever `lambda`. While `lambda h` exceeds DOPRI5's stability
//! boundary at the steps accuracy allows (`h` about 0.1 at rtol 1e-6), an explicit method is
//! held by stability; once `lambda` has decayed, it is not.

use crate::system::OdeSystem;
use crate::{Matrix, State};

pub struct FadingStiffness {
    pub lambda0: f64,
    pub decay: f64,
}

impl FadingStiffness {
    fn lambda(&self, t: f64) -> f64 {
        self.lambda0 * (-self.decay * t).exp()
    }

    pub fn exact(t: f64) -> State<1> {
        State::<1>::new(t.sin())
    }
}

impl OdeSystem<1> for FadingStiffness {
    fn rhs(&self, t: f64, y: &State<1>) -> State<1> {
        State::<1>::new(-self.lambda(t) * (y[0] - t.sin()) + t.cos())
    }

    fn jacobian(&self, t: f64, _y: &State<1>) -> Option<Matrix<1>> {
        Some(Matrix::<1>::new(-self.lambda(t)))
    }

    fn time_derivative(&self, t: f64, y: &State<1>) -> Option<State<1>> {
        let l = self.lambda(t);
        Some(State::<1>::new(
            self.decay * l * (y[0] - t.sin()) + l * t.cos() - t.sin(),
        ))
    }
}
