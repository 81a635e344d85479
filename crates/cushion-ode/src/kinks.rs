//! Kinks: where `f` loses smoothness without a change of regime, and the steps that end on
//! them.
//!
//! A law such as an orifice's `v |v|` has a jump in its second derivative where `v` changes
//! sign: along the solution, a jump in the third derivative of `y`. The local error of a step
//! across that point falls only like the cube of the kink's distance from the step's nearer
//! end, whatever the method's order; and an embedded pair's two solutions, which share their
//! stages, both carry that error, so its estimate misses most of it. An eighth-order method,
//! whose steps are long, is rejected at such a kink, often two or three times, each retry
//! barely smaller (its controller expects the error to fall like `h^8`), and the steps it
//! accepts across kinks add errors its estimate does not see (`tests/integrator/kinks.rs`: 38 to 268
//! times the tolerance). A step that ends where the function crosses zero is smooth.
//!
//! The system names such functions ([`OdeSystem::kink_count`], [`OdeSystem::kink`]). After
//! each accepted step the loop forecasts the next crossing of each one that closes on zero,
//! with the quadratic the events use (`crossing_forecast.rs`), and ends the next step there.
//! Unlike an event, a kink is never located, logged or handled, and the method does not
//! restart after it: nothing in `f` changes but its smoothness.
//!
//! Only DOP853 lands on them ([`crate::stepper::Stepper::lands_on_kinks`]). DOPRI5 misses
//! its tolerance across kinks too on `tests/integrator/kinks.rs`'s problem, but on the hydraulic paper
//! scenes (rtol 1e-4 to 1e-9) its steps are short enough that landing gave errors both ways for
//! 1 to 10 % more evaluations.

use crate::crossing_forecast::{closes_within_reach, zero_after};
use crate::dense::DenseOutput;
use crate::system::OdeSystem;
use crate::State;

/// The most kink functions a system may name.
pub const MAX_KINKS: usize = 4;

/// A forecast crossing nearer the step's start than this share of the step is not landed on:
/// the step runs over it. What a kink inside a step adds to its error grows like the cube of
/// its distance from the nearer end (`tests/integrator/kinks.rs`: `v |v|` under the integral), so a step
/// is landed on the crossing itself, not past it as on an event's, and a kink a thousandth
/// into a step adds a billionth of what one in its middle does; at a hundredth, the error of
/// `tests/integrator/kinks.rs`'s problem at tolerance 1e-8 was 6.9e-7 instead of 1.3e-8.
const KINK_SLIVER: f64 = 1e-3;

/// The kink functions' values at the last accepted point and the next forecast crossing.
pub(crate) struct KinkForecast {
    /// How many functions are followed (0: none, or a method that does not land on them).
    n: usize,
    g: [f64; MAX_KINKS],
    next_crossing: f64,
}

impl KinkForecast {
    /// Follow `n` kink functions (at most [`MAX_KINKS`]).
    pub(crate) fn new(n: usize) -> Self {
        KinkForecast {
            n: n.min(MAX_KINKS),
            g: [0.0; MAX_KINKS],
            next_crossing: f64::INFINITY,
        }
    }

    /// Start anew at `(t, y)` (the run's start, or after a restart): no forecast yet.
    pub(crate) fn reset<S: OdeSystem<N>, const N: usize>(&mut self, sys: &S, t: f64, y: &State<N>) {
        for (i, g) in self.g[..self.n].iter_mut().enumerate() {
            *g = sys.kink(i, t, y);
        }
        self.next_crossing = f64::INFINITY;
    }

    /// After an accepted step from `t0` to `t1` (ending at `y1`, with dense output `dense`):
    /// the first crossing forecast past `t1`, of the functions that close on zero within
    /// reach (`crossing_forecast::closes_within_reach`). On a step held by stability, DOP853's
    /// dense output at the middle may be off, and so the forecast: a step ended early costs a
    /// step, not accuracy.
    pub(crate) fn after_step<S: OdeSystem<N>, const N: usize>(
        &mut self,
        sys: &S,
        dense: &DenseOutput<N>,
        (t0, t1): (f64, f64),
        y1: &State<N>,
    ) {
        if self.n == 0 {
            return;
        }
        let span = t1 - t0;
        let t_mid = t0 + 0.5 * span;
        let mut y_mid = None;
        let mut next = f64::INFINITY;
        for i in 0..self.n {
            let (a, b) = (self.g[i], sys.kink(i, t1, y1));
            self.g[i] = b;
            if !closes_within_reach(a, b) {
                continue;
            }
            let y = *y_mid.get_or_insert_with(|| dense.eval(t_mid));
            if let Some(tau) = zero_after(span, a, sys.kink(i, t_mid, &y), b) {
                next = next.min(t1 + tau);
            }
        }
        self.next_crossing = next;
    }

    /// The length of a step from `t` that ends at the forecast crossing, if that is shorter
    /// than `h` and not a sliver of it.
    pub(crate) fn landing(&self, t: f64, h: f64) -> Option<f64> {
        let to_kink = self.next_crossing - t;
        (to_kink < h && to_kink > KINK_SLIVER * h).then_some(to_kink)
    }
}
