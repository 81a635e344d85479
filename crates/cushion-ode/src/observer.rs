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

/// An observer held by reference: what a caller that keeps its observers passes.
impl<S, const N: usize, O: Observer<S, N> + ?Sized> Observer<S, N> for &mut O {
    #[inline]
    fn on_step(&mut self, sys: &S, step: &Step<'_, N>) {
        (**self).on_step(sys, step);
    }
    #[inline]
    fn after_step(&mut self, sys: &S, step: &Step<'_, N>, ctl: &mut Control) {
        (**self).after_step(sys, step, ctl);
    }
    #[inline]
    fn after_events(&mut self, sys: &S) {
        (**self).after_events(sys);
    }
    #[inline]
    fn before_time_stop(&mut self, sys: &S) {
        (**self).before_time_stop(sys);
    }
    #[inline]
    fn after_time_stop(&mut self, sys: &S, t: f64, y: &State<N>, ctl: &mut Control) {
        (**self).after_time_stop(sys, t, y, ctl);
    }
    #[inline]
    fn after_switch(&mut self, sys: &S, to: Method) {
        (**self).after_switch(sys, to);
    }
}

/// An observer that may be absent (a trajectory nobody asked for): `None` sees nothing.
impl<S, const N: usize, O: Observer<S, N>> Observer<S, N> for Option<O> {
    #[inline]
    fn on_step(&mut self, sys: &S, step: &Step<'_, N>) {
        if let Some(o) = self {
            o.on_step(sys, step);
        }
    }
    #[inline]
    fn after_step(&mut self, sys: &S, step: &Step<'_, N>, ctl: &mut Control) {
        if let Some(o) = self {
            o.after_step(sys, step, ctl);
        }
    }
    #[inline]
    fn after_events(&mut self, sys: &S) {
        if let Some(o) = self {
            o.after_events(sys);
        }
    }
    #[inline]
    fn before_time_stop(&mut self, sys: &S) {
        if let Some(o) = self {
            o.before_time_stop(sys);
        }
    }
    #[inline]
    fn after_time_stop(&mut self, sys: &S, t: f64, y: &State<N>, ctl: &mut Control) {
        if let Some(o) = self {
            o.after_time_stop(sys, t, y, ctl);
        }
    }
    #[inline]
    fn after_switch(&mut self, sys: &S, to: Method) {
        if let Some(o) = self {
            o.after_switch(sys, to);
        }
    }
}

/// Two observers as one, in the shape of OrdinaryDiffEq's `CallbackSet`: each hook goes to the
/// first, then to the second (nest pairs for more). Either may end the run; the other still
/// sees the hook that ended it.
impl<S, const N: usize, A: Observer<S, N>, B: Observer<S, N>> Observer<S, N> for (A, B) {
    #[inline]
    fn on_step(&mut self, sys: &S, step: &Step<'_, N>) {
        self.0.on_step(sys, step);
        self.1.on_step(sys, step);
    }
    #[inline]
    fn after_step(&mut self, sys: &S, step: &Step<'_, N>, ctl: &mut Control) {
        self.0.after_step(sys, step, ctl);
        self.1.after_step(sys, step, ctl);
    }
    #[inline]
    fn after_events(&mut self, sys: &S) {
        self.0.after_events(sys);
        self.1.after_events(sys);
    }
    #[inline]
    fn before_time_stop(&mut self, sys: &S) {
        self.0.before_time_stop(sys);
        self.1.before_time_stop(sys);
    }
    #[inline]
    fn after_time_stop(&mut self, sys: &S, t: f64, y: &State<N>, ctl: &mut Control) {
        self.0.after_time_stop(sys, t, y, ctl);
        self.1.after_time_stop(sys, t, y, ctl);
    }
    #[inline]
    fn after_switch(&mut self, sys: &S, to: Method) {
        self.0.after_switch(sys, to);
        self.1.after_switch(sys, to);
    }
}
