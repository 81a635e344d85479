//! What watches a run beside the problem, in the shape of OrdinaryDiffEq's callbacks beside its
//! `ODEProblem`: the problem ([`OdeSystem`]: right-hand side, Jacobian, event functions and
//! their handlers) says what is integrated; an observer sees every accepted step, the events and
//! time stops the problem handled and every change of method, with the problem as it stands,
//! and may end the run through [`Control::stop`]. It never changes the state. [`solve`] runs
//! without one; [`solve_observed`] with one.
//!
//! [`OdeSystem`]: crate::OdeSystem
//! [`solve`]: crate::solve
//! [`solve_observed`]: crate::solve_observed

use crate::system::{Control, Step};
use crate::{Method, State};

/// An observer of the integration of the problem `S` (every hook defaults to nothing).
pub trait Observer<S, const N: usize> {
    /// An accepted step, before the problem's own `on_step`.
    #[inline]
    fn on_step(&mut self, _sys: &S, _step: &Step<'_, N>) {}

    /// The same step after the problem's `on_step`; `ctl.stop()` ends the run at its end.
    #[inline]
    fn after_step(&mut self, _sys: &S, _step: &Step<'_, N>, _ctl: &mut Control) {}

    /// The problem handled the events of one instant (one or several crossings at `t`).
    #[inline]
    fn after_events(&mut self, _sys: &S) {}

    /// A time stop at `t` is about to be handled by the problem.
    #[inline]
    fn before_time_stop(&mut self, _sys: &S) {}

    /// The problem handled the time stop at `(t, y)`; `ctl.stop()` ends the run there.
    #[inline]
    fn after_time_stop(&mut self, _sys: &S, _t: f64, _y: &State<N>, _ctl: &mut Control) {}

    /// The integrator changed its method (`auto`), after the problem's `on_switch`.
    #[inline]
    fn after_switch(&mut self, _sys: &S, _to: Method) {}
}

/// No observer: what [`crate::solve`] runs with.
impl<S, const N: usize> Observer<S, N> for () {}
