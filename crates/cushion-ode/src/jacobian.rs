//! Finite-difference approximations of `df/dy` and `df/dt`, for systems that give neither
//! ([`crate::OdeSystem::jacobian`], [`crate::OdeSystem::time_derivative`]).
//!
//! Forward differences with Hairer's increments (the codes RADAU5 and RODAS, Hairer & Wanner,
//! *Solving ODEs II*): `delta_j = sqrt(eps max(1e-5, |y_j|))` for column `j`,
//! `sqrt(eps max(1e-5, |t|))` for `t`, with `eps` the rounding unit; the square root balances
//! the truncation error (`~ delta`) against the rounding error (`~ eps / delta`). Each
//! difference is divided by the increment actually made, `(y_j + delta) - y_j`, which is exact
//! in floating point, so an `f` linear in `y_j` gets its column to rounding.

use crate::system::OdeSystem;
use crate::{Matrix, State};

/// `df/dy` at `(t, y)` by forward differences, column by column; `f0 = f(t, y)`. Costs `N`
/// evaluations of `f`.
pub fn finite_difference_jacobian<S: OdeSystem<N>, const N: usize>(
    sys: &S,
    t: f64,
    y: &State<N>,
    f0: &State<N>,
) -> Matrix<N> {
    let mut jac = Matrix::<N>::zeros();
    let mut yd = *y;
    for c in 0..N {
        let yc = y[c];
        yd[c] = yc + (f64::EPSILON * yc.abs().max(1e-5)).sqrt();
        let delta = yd[c] - yc;
        jac.set_column(c, &((sys.rhs(t, &yd) - f0) / delta));
        yd[c] = yc;
    }
    jac
}

/// `df/dt` at `(t, y)` by a forward difference; `f0 = f(t, y)`. Costs one evaluation of `f`.
pub fn finite_difference_time_derivative<S: OdeSystem<N>, const N: usize>(
    sys: &S,
    t: f64,
    y: &State<N>,
    f0: &State<N>,
) -> State<N> {
    let t1 = t + (f64::EPSILON * t.abs().max(1e-5)).sqrt();
    (sys.rhs(t1, y) - f0) / (t1 - t)
}
