//! One step of a method. [`ExplicitRk`] reads any [`Tableau`]; an implicit method will be
//! another [`Stepper`] behind the same loop in `solve.rs`.

use crate::dense::DenseOutput;
use crate::system::OdeSystem;
use crate::tableau::{Tableau, MAX_STAGES};
use crate::State;

/// One attempted step from `(t, y)` with slope `f0` and size `h`.
#[derive(Clone, Copy, Debug)]
pub struct Attempt<const N: usize> {
    /// Proposed state at `t + h`.
    pub y1: State<N>,
    /// `f(t + h, y1)` (FSAL: the next step's first stage).
    pub f1: State<N>,
    /// Local error estimate (unscaled), when the method has one.
    pub err: Option<State<N>>,
}

/// A one-step method.
pub trait Stepper<const N: usize> {
    /// Order used by the step-size controller (of the propagated solution).
    fn order(&self) -> u32;
    /// Whether `err` is estimated (adaptive step size).
    fn is_adaptive(&self) -> bool;
    /// Right-hand-side evaluations one attempt costs (including `f1`).
    fn rhs_evals_per_step(&self) -> u64;
    /// Attempt a step.
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
    ) -> Attempt<N>;
    /// Dense output of the last attempt (valid once it is accepted).
    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        y1: &State<N>,
        f0: &State<N>,
        f1: &State<N>,
    ) -> DenseOutput<N>;
    /// Hairer's stiffness quotient `h * |lambda|` estimate of the last attempt, if the method has one.
    fn stiffness_estimate(&self, h: f64, y1: &State<N>, f1: &State<N>) -> Option<f64>;
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
    fn order(&self) -> u32 {
        self.tab.order
    }

    fn is_adaptive(&self) -> bool {
        !self.tab.e.is_empty()
    }

    fn rhs_evals_per_step(&self) -> u64 {
        self.tab.c.len() as u64 // stages 2..s plus f1
    }

    #[inline]
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
    ) -> Attempt<N> {
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
        Attempt { y1, f1, err }
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        y1: &State<N>,
        f0: &State<N>,
        f1: &State<N>,
    ) -> DenseOutput<N> {
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
        DenseOutput::new(t, h, y0, y1, f0, f1, r5)
    }

    fn stiffness_estimate(&self, h: f64, y1: &State<N>, f1: &State<N>) -> Option<f64> {
        if self.tab.e.is_empty() || self.tab.c.len() < 2 || self.tab.c[self.tab.c.len() - 1] != 1.0
        {
            return None;
        }
        // Two evaluations at t + h: f(last stage input) and f(y1) (Hairer, DOPRI5).
        let s = self.tab.c.len();
        crate::stiffness::h_lambda(h, y1, f1, &self.last_stage_input, &self.k[s - 1])
    }
}
