//! The problem: a right-hand side, its event functions and what happens at them.

use crate::dense::DenseOutput;
use crate::{Matrix, State};

/// At most this many event functions per system (they are evaluated into a stack array).
pub const MAX_EVENTS: usize = 16;

/// Which sign changes of an event function `g` count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// `g` goes from negative to zero or positive.
    Rising,
    /// `g` goes from positive to zero or negative.
    Falling,
    /// Either.
    Both,
}

impl Direction {
    /// Does a change from `a` (the value before) to `b` (the value after) count?
    /// A function that is exactly zero before does not fire (CVODE's rule): `a` must be strictly
    /// on one side.
    #[inline]
    pub fn crosses(self, a: f64, b: f64) -> bool {
        let rising = a < 0.0 && b >= 0.0;
        let falling = a > 0.0 && b <= 0.0;
        match self {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Both => rising || falling,
        }
    }
}

/// What the integrator does after an event (or a time stop) has been handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Record it and keep going; the step stands, later crossings inside it are still found.
    Continue,
    /// The handler changed the state and/or the regime of the right-hand side: the step is cut
    /// at the event, `f` is evaluated again and the step size is selected anew.
    Restart,
    /// Record it and end the integration here (status `StoppedByEvent`).
    Stop,
}

/// What a handler may ask of the integrator besides its return value.
#[derive(Debug)]
pub struct Control {
    /// Room for a few stops is reserved once per run, so the step loop does not allocate.
    pub(crate) new_time_stops: Vec<f64>,
    pub(crate) stop_requested: bool,
}

impl Control {
    pub(crate) fn new() -> Self {
        Control {
            new_time_stops: Vec::with_capacity(8),
            stop_requested: false,
        }
    }

    /// Step onto time `t` exactly (a point where the right-hand side is not smooth), never
    /// across it. Times at or before the current time, at or after the end, or not finite are
    /// ignored; any number may be asked for.
    pub fn add_time_stop(&mut self, t: f64) {
        self.new_time_stops.push(t);
    }

    /// End the integration after this step (status `StoppedByEvent`); used for early ends.
    pub fn stop(&mut self) {
        self.stop_requested = true;
    }
}

/// One accepted step as an observer sees it: `[t0, t1]`, its end states, and the dense output,
/// valid on the whole interval.
pub struct Step<'a, const N: usize> {
    pub t0: f64,
    pub t1: f64,
    pub y0: &'a State<N>,
    pub y1: &'a State<N>,
    pub dense: &'a DenseOutput<N>,
    /// Whether the dense output is stable on this step: `false` where the method's estimate
    /// of `h |lambda|` is above 0.6 of its dense output's stability boundary (DOP853's, on a
    /// step held by stability: [`crate::stepper::Stepper::dense_stability_boundary`]), or where
    /// such a method had no estimate ([`crate::stiffness::dense_stable`]). Inside such a step a fast mode's
    /// deviation, held to the tolerance at the ends, may be amplified many times; an observer
    /// that needs the state there to the tolerance integrates the step again in shorter ones.
    pub dense_stable: bool,
}

impl<const N: usize> Step<'_, N> {
    /// The state at `t` in `[t0, t1]`, from the dense output.
    #[inline]
    pub fn at(&self, t: f64) -> State<N> {
        self.dense.eval(t)
    }
}

/// An ODE `y' = f(t, y)` with optional events. The system may carry a discrete regime (which
/// branch of a piecewise law is active); only the handlers change it.
pub trait OdeSystem<const N: usize> {
    /// `f(t, y)` in the current regime.
    fn rhs(&self, t: f64, y: &State<N>) -> State<N>;

    /// The Jacobian `df/dy` at `(t, y)` in the current regime, for the implicit method
    /// ([`crate::Method::Rodas`]); the explicit methods never ask. `None` (the default): it is
    /// approximated by finite differences, column by column, `N` evaluations of `f` each time.
    fn jacobian(&self, _t: f64, _y: &State<N>) -> Option<Matrix<N>> {
        None
    }

    /// `df/dt` at `(t, y)` in the current regime, for the implicit method, which needs it
    /// whenever `f` depends on `t`. `None` (the default): a finite difference in `t`, one
    /// evaluation of `f` with each Jacobian. An autonomous system returns `Some(zero)` and
    /// saves that evaluation.
    fn time_derivative(&self, _t: f64, _y: &State<N>) -> Option<State<N>> {
        None
    }

    /// `df/dy` and `df/dt` together, for a system that computes both in one pass (the
    /// implicit method asks this way, once per starting point). The default asks
    /// [`OdeSystem::jacobian`] and [`OdeSystem::time_derivative`].
    fn jacobians(&self, t: f64, y: &State<N>) -> (Option<Matrix<N>>, Option<State<N>>) {
        (self.jacobian(t, y), self.time_derivative(t, y))
    }

    /// How many event functions there are (at most [`MAX_EVENTS`]).
    fn event_count(&self) -> usize {
        0
    }

    /// Evaluate every event function `g_i(t, y)` into `g[..event_count()]`.
    fn events(&self, _t: f64, _y: &State<N>, _g: &mut [f64]) {}

    /// Event function `g_i(t, y)` alone, for the root finder, which follows one function at a
    /// time. It must equal `events`' `g[i]` to the bit; the default computes them all and
    /// returns that one. Override it where one function is much cheaper than all.
    fn event(&self, i: usize, t: f64, y: &State<N>) -> f64 {
        let mut g = [0.0; MAX_EVENTS];
        let n = self.event_count().min(MAX_EVENTS);
        self.events(t, y, &mut g[..n]);
        g[i]
    }

    /// How many kink functions there are (at most [`crate::kinks::MAX_KINKS`]; more end the
    /// run with `InvalidInput`): functions of `(t, y)` whose zeros are where `f` loses
    /// smoothness without a change of regime (a jump in one of its derivatives, such as
    /// `v |v|` where `v` changes sign). The methods that suffer most from a step across one
    /// end their steps on each forecast crossing (`kinks.rs`); they are never located, logged
    /// or handled. None by default.
    fn kink_count(&self) -> usize {
        0
    }

    /// Kink function `i` at `(t, y)` (see [`OdeSystem::kink_count`]).
    fn kink(&self, _i: usize, _t: f64, _y: &State<N>) -> f64 {
        1.0
    }

    /// Which sign changes of `g_i` count.
    fn event_direction(&self, _i: usize) -> Direction {
        Direction::Both
    }

    /// Whether `f`, in the current regime, loses smoothness where `g_i` is zero: a contact
    /// force `k delta^1.5` with `delta` the penetration `g_i`, which vanishes as the contact
    /// ends. For a method whose error estimate misses what such a point costs a step
    /// ([`crate::stepper::Stepper::lands_on_kinks`]), the loop asks twice:
    /// - before the handlers, of a crossing found well inside a step: the step is not kept but
    ///   taken again to end just past the crossing (`events.rs`, "Kinked crossings");
    /// - after the handlers restarted the run at event `i`, in the new regime (a contact has
    ///   just begun, its force sets in like `delta^1.5` where the first step starts): that
    ///   step is judged by the more cautious of the method's estimates (`solve/attempt.rs`).
    ///
    /// False by default: a regime that only the handlers switch usually leaves `f` smooth
    /// across the crossing (a contact's onset before its handler, a threshold only recorded).
    fn kinked_at_event(&self, _i: usize) -> bool {
        false
    }

    /// Optional, for a cheaper event scan: a bound of how far `g_i(t, y(t))` can stray, for `t`
    /// in `[t0, t1]`, from the straight line between its values at `t0` and `t1`, when each
    /// component `y_j(t)` of the step's dense output strays at most `deviation[j]` from its own
    /// chord. For `g_i(t, y) = c . y + r(t)` (affine in the state) it is
    /// `sum_j |c_j| deviation[j] + max |r - chord of r|`. A step on which every event function
    /// has one strict sign at both ends and a bound below its smaller end value holds no
    /// crossing, and is not sampled inside. `None` (the default): the step is sampled at the
    /// interior points (`SolverOptions::event_subdivisions`).
    fn event_chord_bound(
        &self,
        _i: usize,
        _t0: f64,
        _t1: f64,
        _deviation: &State<N>,
    ) -> Option<f64> {
        None
    }

    /// [`OdeSystem::event_chord_bound`] of every event function at once, into
    /// `bounds[..event_count()]`, NaN where there is none. The integrator asks this way, once
    /// per step; override it where computing the bounds together is cheaper than one by one.
    fn event_chord_bounds(&self, t0: f64, t1: f64, deviation: &State<N>, bounds: &mut [f64]) {
        for (i, b) in bounds.iter_mut().enumerate() {
            *b = self
                .event_chord_bound(i, t0, t1, deviation)
                .unwrap_or(f64::NAN);
        }
    }

    /// Called at a located crossing of `g_i`, at time `t` (on the far side of the crossing).
    /// It may change `y` and the regime; it must say so by returning `Restart`.
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        _y: &mut State<N>,
        _ctl: &mut Control,
    ) -> EventAction {
        EventAction::Stop
    }

    /// Called when a time stop is reached exactly. `f` is always evaluated again afterwards.
    /// The step that lands on a stop evaluates `f` at the stop's time, so a right-hand side
    /// that jumps there must switch its regime here rather than by comparing `t`; one that is
    /// only kinked (continuous) may compare `t`.
    fn on_time_stop(&mut self, _t: f64, _y: &mut State<N>, _ctl: &mut Control) -> EventAction {
        EventAction::Continue
    }

    /// Called when `Method::Auto` changes method, at `(t, y)`, between two steps: `to` takes
    /// the next one.
    fn on_switch(&mut self, _t: f64, _y: &State<N>, _to: crate::Method) {}

    /// Called after every accepted step (after events cut it); may call `ctl.stop()`.
    fn on_step(&mut self, _step: &Step<'_, N>, _ctl: &mut Control) {}
}
