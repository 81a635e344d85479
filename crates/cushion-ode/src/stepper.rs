//! One step of a method, behind one trait the loop in `solve.rs` drives: the explicit
//! Runge–Kutta methods ([`ExplicitRk`] reading any [`Tableau`], and [`crate::dopri5::Dopri5`])
//! and the Rosenbrock method ([`crate::rodas::Rodas`]).

use crate::controller::{Controller, PiController};
use crate::dense::DenseOutput;
pub use crate::failure::StepFailure;
use crate::options::{Method, SolverOptions};
use crate::solution::Stats;
use crate::system::OdeSystem;
use crate::tableau::{Tableau, MAX_STAGES};
use crate::{Matrix, State};
use std::cell::Cell;

/// One attempted step from `(t, y)` with slope `f0` and size `h`.
#[derive(Clone, Copy, Debug)]
pub struct Attempt<const N: usize> {
    /// Proposed state at `t + h`.
    pub y1: State<N>,
    /// `f(t + h, y1)` when the method evaluated it (FSAL: the next step's first stage); `None`
    /// when it did not, and the loop evaluates it once the step is accepted and not cut.
    pub f1: Option<State<N>>,
    /// Local error estimate (unscaled), when the method has one.
    pub err: Option<State<N>>,
    /// A second, lower-order estimate that the error norm combines with `err` as Hairer's
    /// DOP853 does (`err5^2 / sqrt(err5^2 + 0.01 err3^2)`, [`crate::dop853`]); `None` for the
    /// other methods, whose norm is that of `err` alone.
    pub err_low: Option<State<N>>,
}

impl<const N: usize> Attempt<N> {
    /// A place for an attempt (zeros, no slopes, no estimates), before the first is written.
    pub fn empty() -> Self {
        Attempt {
            y1: State::<N>::zeros(),
            f1: None,
            err: None,
            err_low: None,
        }
    }
}

/// A change of method between two steps (`auto.rs`), which the loop takes from
/// [`Stepper::take_switch`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Switch {
    /// The method from the next step on.
    pub to: Method,
    /// When the run of steps that decided it began.
    pub since: f64,
    /// The new method is the one for stiff problems, taken because the steps were held by
    /// stability: the run counts as stiff from `since` ([`Stats::stiff`]).
    pub to_stiff: bool,
    /// The largest next step the new method may take (infinite: no bound).
    pub h_max: f64,
}

/// A one-step method.
///
/// The loop calls [`Stepper::step_into`] for each attempt and tells the method what became of it:
/// [`Stepper::accepted`], [`Stepper::rejected`] (error too large, or a failure), and
/// [`Stepper::restart`] when a handler changed the state or the regime (an event's `Restart`,
/// a time stop). A method that caches something of its starting point (a Jacobian, a
/// factorization) drops it there.
pub trait Stepper<const N: usize> {
    /// The step-size controller that suits the method.
    type Controller: Controller;

    /// Order of the propagated solution (used by the initial step selection).
    fn order(&self) -> u32;
    /// Whether `err` is estimated (adaptive step size).
    fn is_adaptive(&self) -> bool;
    /// The method's step-size controller, from the settings.
    fn controller(&self, opts: &SolverOptions) -> Self::Controller;
    /// Attempt a step, written into `out`, which the loop keeps from one attempt to the next
    /// (an attempt holds four states: moving it by value would copy each on every attempt).
    /// `out` is unspecified after a failure. Every evaluation of `f` goes through `sys` (the
    /// loop counts them there).
    fn step_into<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
        out: &mut Attempt<N>,
    ) -> Result<(), StepFailure>;
    /// [`Stepper::step_into`] into a new attempt.
    #[inline]
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
    ) -> Result<Attempt<N>, StepFailure> {
        let mut a = Attempt::empty();
        self.step_into(sys, t, y, f0, h, &mut a)?;
        Ok(a)
    }
    /// The last attempt, from `(t, y)` with size `h`, was accepted: the evaluations a method
    /// makes only for an accepted step, before its stiffness estimate and dense output are
    /// asked for (DOP853: `f(y1)` into `a.f1`, and the three stages of its continuous
    /// extension). Every evaluation goes through `sys` (counted). Returns whether it evaluated
    /// anything (the loop then checks the new numbers are finite). Nothing by default.
    #[inline]
    fn complete<S: OdeSystem<N>>(
        &mut self,
        _sys: &S,
        _t: f64,
        _y: &State<N>,
        _h: f64,
        _a: &mut Attempt<N>,
    ) -> bool {
        false
    }
    /// Dense output of the last attempt on `[t, t + h]` (valid once it is accepted).
    fn dense(&self, t: f64, h: f64, y0: &State<N>, f0: &State<N>, a: &Attempt<N>)
        -> DenseOutput<N>;
    /// Hairer's stiffness quotient `h * |lambda|` estimated from the last attempt, if the
    /// method has one.
    fn stiffness_estimate(&self, h: f64, a: &Attempt<N>) -> Option<f64>;
    /// The threshold on [`Stepper::stiffness_estimate`] above which a step counts as held by
    /// stability: 0.9 of the method's stability boundary (DOPRI5's by default).
    #[inline]
    fn stiffness_threshold(&self) -> f64 {
        crate::stiffness::THRESHOLD
    }
    /// The largest `h |lambda|` on the negative real axis up to which the dense output is
    /// stable: `|P(theta, -x)| <= 1` for every `theta` in the step, `P` being what it makes of
    /// `y' = lambda y`. Infinite (the default) where it is stable wherever the step is:
    /// DOPRI5's stays within the step's own `|R(z)|` up to its stability boundary, and the
    /// implicit methods' are built for stiff steps. DOP853's is finite
    /// ([`crate::dop853::DENSE_STABILITY_BOUNDARY`]).
    #[inline]
    fn dense_stability_boundary(&self) -> f64 {
        f64::INFINITY
    }
    /// The `h |lambda|` ([`Stepper::stiffness_estimate`]) above which an accepted step that
    /// jumped (`step_guard.rs`, `GUARD_GROWTH`) is taken again, shorter: for a method whose error
    /// estimate can pass a step past its stability boundary. Infinite (the default) where the
    /// estimate grows with the step past it, as DOPRI5's does; DOP853's boundary for it
    /// ([`crate::dop853::STABILITY_GUARD`]).
    #[inline]
    fn stability_guard(&self) -> f64 {
        f64::INFINITY
    }
    /// Whether the loop ends this method's steps on the system's forecast kinks
    /// ([`crate::system::OdeSystem::kink_count`], `kinks.rs`): for a method of high order,
    /// whose long steps a kink inside costs rejections and errors its estimate misses. False
    /// by default (DOPRI5's steps on the paper scenes are short enough: `kinks.rs`).
    #[inline]
    fn lands_on_kinks(&self) -> bool {
        false
    }
    /// The last attempt was accepted: the next starts from a new point.
    #[inline]
    fn accepted(&mut self) {}
    /// The last attempt was rejected or failed: the next starts from the same point.
    #[inline]
    fn rejected(&mut self) {}
    /// A handler changed the state or the regime of `f`: nothing cached still holds.
    #[inline]
    fn restart(&mut self) {}
    /// After an accepted step (its dense output used, its observers told): a composite method's
    /// change of method from the next step on ([`crate::auto`]). The loop then takes the new
    /// method's controller.
    #[inline]
    fn take_switch(&mut self) -> Option<Switch> {
        None
    }
    /// Add the method's own counts (Jacobians, factorizations) to `stats`.
    #[inline]
    fn add_counts(&self, _stats: &mut Stats) {}
}

/// The system as a step sees it: `f` counted as it is evaluated, the Jacobian and `df/dt`
/// passed through. Only for the inside of a step: it has no events.
pub(crate) struct Counted<'a, S> {
    sys: &'a S,
    evals: Cell<u64>,
}

impl<'a, S> Counted<'a, S> {
    #[inline]
    pub fn new(sys: &'a S) -> Self {
        Counted {
            sys,
            evals: Cell::new(0),
        }
    }

    /// Evaluations of `f` so far.
    #[inline]
    pub fn evals(&self) -> u64 {
        self.evals.get()
    }
}

impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for Counted<'_, S> {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.evals.set(self.evals.get() + 1);
        self.sys.rhs(t, y)
    }

    #[inline]
    fn jacobian(&self, t: f64, y: &State<N>) -> Option<Matrix<N>> {
        self.sys.jacobian(t, y)
    }

    #[inline]
    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        self.sys.time_derivative(t, y)
    }

    #[inline]
    fn jacobians(&self, t: f64, y: &State<N>) -> (Option<Matrix<N>>, Option<State<N>>) {
        self.sys.jacobians(t, y)
    }
}

/// An explicit Runge–Kutta method given by its tableau. Stages live on the stack.
pub struct ExplicitRk<const N: usize> {
    tab: &'static Tableau,
    k: [State<N>; MAX_STAGES],
    /// Input of the last stage (for the stiffness test: stage 6 of DOPRI5, at `t + h`).
    last_stage_input: State<N>,
}

impl<const N: usize> ExplicitRk<N> {
    pub fn new(tab: &'static Tableau) -> Self {
        ExplicitRk {
            tab,
            k: [State::<N>::zeros(); MAX_STAGES],
            last_stage_input: State::<N>::zeros(),
        }
    }
}

impl<const N: usize> Stepper<N> for ExplicitRk<N> {
    type Controller = PiController;

    fn order(&self) -> u32 {
        self.tab.order
    }

    fn is_adaptive(&self) -> bool {
        !self.tab.e.is_empty()
    }

    fn controller(&self, opts: &SolverOptions) -> PiController {
        PiController::new(
            self.tab.order,
            opts.safety,
            opts.beta,
            opts.min_ratio,
            opts.max_ratio,
        )
    }

    #[inline]
    fn step_into<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
        out: &mut Attempt<N>,
    ) -> Result<(), StepFailure> {
        let tab = self.tab;
        let s = tab.c.len();
        self.k[0] = *f0;
        let mut yi = *y;
        for i in 1..s {
            yi = *y;
            for (j, a) in tab.a[i].iter().enumerate() {
                if *a != 0.0 {
                    yi += self.k[j] * (h * a);
                }
            }
            self.k[i] = sys.rhs(t + tab.c[i] * h, &yi);
        }
        self.last_stage_input = yi;
        let mut y1 = *y;
        for (j, b) in tab.b.iter().enumerate() {
            if *b != 0.0 {
                y1 += self.k[j] * (h * b);
            }
        }
        let f1 = sys.rhs(t + h, &y1);
        let err = if tab.e.is_empty() {
            None
        } else {
            let mut e = f1 * (h * tab.e[s]);
            for j in 0..s {
                if tab.e[j] != 0.0 {
                    e += self.k[j] * (h * tab.e[j]);
                }
            }
            Some(e)
        };
        *out = Attempt {
            y1,
            f1: Some(f1),
            err,
            err_low: None,
        };
        Ok(())
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        let f1 =
            a.f1.as_ref()
                .expect("an explicit Runge-Kutta attempt carries f1");
        let s = self.tab.c.len();
        let mut r5 = State::<N>::zeros();
        if !self.tab.d.is_empty() {
            r5 = f1 * (h * self.tab.d[s]);
            for j in 0..s {
                if self.tab.d[j] != 0.0 {
                    r5 += self.k[j] * (h * self.tab.d[j]);
                }
            }
        }
        DenseOutput::new(t, h, y0, &a.y1, f0, f1, r5)
    }

    fn stiffness_estimate(&self, h: f64, a: &Attempt<N>) -> Option<f64> {
        if self.tab.e.is_empty() || self.tab.c.len() < 2 || self.tab.c[self.tab.c.len() - 1] != 1.0
        {
            return None;
        }
        // Two evaluations at t + h: f(last stage input) and f(y1) (Hairer, DOPRI5).
        let s = self.tab.c.len();
        crate::stiffness::h_lambda(
            h,
            &a.y1,
            a.f1.as_ref()?,
            &self.last_stage_input,
            &self.k[s - 1],
        )
    }
}
