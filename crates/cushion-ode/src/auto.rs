//! Automatic switching between DOPRI5 and the Rosenbrock method (`Method::Auto`), in the shape
//! of OrdinaryDiffEq's `AutoSwitch`: one composite method behind the [`Stepper`] interface, so
//! the loop, events, time stops and output work as for either method alone.
//!
//! - It starts with DOPRI5. Each accepted DOPRI5 step gives Hairer's estimate of `h |lambda|`
//!   (`stiffness::h_lambda`, free: two evaluations the step made anyway); after
//!   [`TO_STIFF_STEPS`] steps in a row above [`stiffness::THRESHOLD`] (0.9 of DOPRI5's
//!   stability boundary, `AutoSwitch`'s `stifftol`) its step is held by stability, not
//!   accuracy, and it switches to Rodas. It also switches after [`PATIENT_STEPS`] steps in a
//!   row above [`PATIENT_FRACTION`] of the boundary (`h |lambda|` about 1): a mode that
//!   decays or turns by a radian or more on every one of that many steps carries nothing the
//!   tolerance resolves, so only stability can hold the steps there. A stiff mode through a
//!   nonlinear law can hold DOPRI5's controller well under the boundary: the compressible
//!   liquid's orifice, laminar below a transition pressure of the size of the tolerance on
//!   `p_m`, held it at `h |lambda|` 1.6-1.7 for a million steps
//!   (`cushion-model/tests/model/auto.rs::a_compressible_liquid_held_under_the_stability_limit_switches`).
//! - Each accepted Rodas step has the Jacobian of its start; the spectral radius `rho` of it
//!   (`stiffness::spectral_radius`, a power iteration) says whether DOPRI5 would be stable
//!   with the step Rodas takes next. After [`TO_NONSTIFF_STEPS`] steps in a row with
//!   `h rho` below [`NONSTIFF_FRACTION`] of the boundary, it switches back, with a first
//!   step no larger than that fraction allows.
//! - Hysteresis: the two thresholds differ (0.9 and 0.5 of the boundary), and each return to
//!   Rodas doubles the count of non-stiff steps the next return to DOPRI5 needs, so a scene
//!   at the edge of stiffness settles on Rodas instead of flipping back and forth.
//!
//! A switch happens between steps: the step that decided it keeps its method's dense output;
//! the loop then asks for the new method's controller and tells the system
//! (`OdeSystem::on_switch`). Both methods start from `f(t, y)`, which the loop keeps, so a
//! switch costs no evaluation.

use crate::controller::{Controller, PiController, PredictiveController};
use crate::dense::DenseOutput;
use crate::dopri5::Dopri5;
use crate::norm::Weights;
use crate::options::{Method, SolverOptions};
use crate::rodas::Rodas;
use crate::solution::Stats;
pub use crate::stepper::Switch;
use crate::stepper::{Attempt, StepFailure, Stepper};
// PATIENT_*: no paper scene or design-space run takes a thousand DOPRI5 steps in a row near
// its stability limit; a run held there takes them in microseconds
use crate::stiffness::{
    self, Run, PATIENT_BREAKS, PATIENT_FRACTION, PATIENT_STEPS, STABILITY_BOUNDARY, THRESHOLD,
};
use crate::system::OdeSystem;
use crate::State;

/// DOPRI5 steps in a row held at the stability limit before switching to Rodas
/// (`AutoSwitch`'s `maxstiffstep`).
pub const TO_STIFF_STEPS: u32 = 10;
/// Steps in a row below the threshold that such a run survives: at the stability limit the
/// controller oscillates and the estimate dips under the threshold now and then (most at
/// loose tolerances), which must not restart the count, while a run broken for longer is an
/// accuracy-bound stretch. Hairer's test tolerates 5.
pub const TO_STIFF_BREAKS: u32 = 2;
/// Rodas steps in a row with room for DOPRI5 before switching back, the first time; doubled
/// by every later return to Rodas.
pub const TO_NONSTIFF_STEPS: u32 = 5;
/// `h rho` below this fraction of DOPRI5's stability boundary counts as room for DOPRI5.
pub const NONSTIFF_FRACTION: f64 = 0.5;

/// The composite method.
pub struct AutoSwitch<const N: usize> {
    explicit: Dopri5<N>,
    implicit: Rodas<N>,
    /// Which method makes the next attempt (false: DOPRI5).
    stiff: bool,
    weights: Weights<N>,
    /// The last attempt's `h |lambda|` (DOPRI5) and its start `(t, y)`.
    h_lambda: Option<f64>,
    t: f64,
    y: State<N>,
    h: f64,
    /// The steps in a row towards a switch: held at the threshold (or, under Rodas, with
    /// room for DOPRI5), and near the limit for the patient switch.
    held: Run,
    near: Run,
    nonstiff_steps_needed: u32,
    pending: Option<Switch>,
    switches: u64,
}

impl<const N: usize> AutoSwitch<N> {
    pub fn new(opts: &SolverOptions) -> Self {
        AutoSwitch {
            explicit: Dopri5::new(),
            implicit: Rodas::new(),
            stiff: false,
            weights: Weights::of(opts),
            h_lambda: None,
            t: 0.0,
            y: State::<N>::zeros(),
            h: 0.0,
            held: Run::default(),
            near: Run::default(),
            nonstiff_steps_needed: TO_NONSTIFF_STEPS,
            pending: None,
            switches: 0,
        }
    }

    /// The method making the next attempt.
    pub fn current(&self) -> Method {
        if self.stiff {
            Method::Rodas
        } else {
            Method::Dp5
        }
    }
}

/// The controller of whichever method is current: each keeps its own.
pub enum AutoController {
    Explicit(PiController),
    Implicit(PredictiveController),
}

impl Controller for AutoController {
    #[inline]
    fn next(&mut self, err: f64, h: f64) -> (bool, f64) {
        match self {
            AutoController::Explicit(c) => c.next(err, h),
            AutoController::Implicit(c) => c.next(err, h),
        }
    }

    #[inline]
    fn after_failure(&mut self, h: f64, failure: StepFailure) -> f64 {
        match self {
            AutoController::Explicit(c) => Controller::after_failure(c, h, failure),
            AutoController::Implicit(c) => c.after_failure(h, failure),
        }
    }

    #[inline]
    fn reset(&mut self) {
        match self {
            AutoController::Explicit(c) => c.reset(),
            AutoController::Implicit(c) => c.reset(),
        }
    }
}

impl<const N: usize> Stepper<N> for AutoSwitch<N> {
    type Controller = AutoController;

    fn order(&self) -> u32 {
        if self.stiff {
            self.implicit.order()
        } else {
            self.explicit.order()
        }
    }

    fn is_adaptive(&self) -> bool {
        true
    }

    fn controller(&self, opts: &SolverOptions) -> AutoController {
        if self.stiff {
            AutoController::Implicit(self.implicit.controller(opts))
        } else {
            AutoController::Explicit(self.explicit.controller(opts))
        }
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
        (self.t, self.y, self.h) = (t, *y, h);
        if self.stiff {
            self.implicit.step_into(sys, t, y, f0, h, out)
        } else {
            self.explicit.step_into(sys, t, y, f0, h, out)?;
            self.h_lambda = self.explicit.stiffness_estimate(h, out);
            Ok(())
        }
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        if self.stiff {
            self.implicit.dense(t, h, y0, f0, a)
        } else {
            self.explicit.dense(t, h, y0, f0, a)
        }
    }

    /// The loop's stiffness test stays silent: a stiff stretch is what this method switches
    /// on, not a failure.
    fn stiffness_estimate(&self, _h: f64, _a: &Attempt<N>) -> Option<f64> {
        None
    }

    fn accepted(&mut self) {
        if self.stiff {
            // DOPRI5 would be stable with the next step if h rho stays within the fraction of
            // its boundary; the step Rodas takes next is at least this one (its controller
            // rarely shrinks an accepted step much), so this step's size is the test.
            let scale = self.weights.scale(&self.y);
            let rho = stiffness::spectral_radius(self.implicit.jacobian(), &scale);
            let room = self.h * rho < NONSTIFF_FRACTION * STABILITY_BOUNDARY;
            self.implicit.accepted();
            if self.held.count(self.t, room, self.nonstiff_steps_needed, 0) {
                self.pending = Some(Switch {
                    to: Method::Dp5,
                    since: self.held.started,
                    to_stiff: false,
                    h_max: if rho > 0.0 {
                        NONSTIFF_FRACTION * STABILITY_BOUNDARY / rho
                    } else {
                        f64::INFINITY
                    },
                });
            }
        } else {
            self.explicit.accepted();
            let above = |limit: f64| self.h_lambda.is_some_and(|hl| hl > limit);
            let (held, near) = (
                above(THRESHOLD),
                above(PATIENT_FRACTION * STABILITY_BOUNDARY),
            );
            let t = self.t;
            let switch_at = if self.held.count(t, held, TO_STIFF_STEPS, TO_STIFF_BREAKS) {
                Some(self.held.started)
            } else if self.near.count(t, near, PATIENT_STEPS, PATIENT_BREAKS) {
                Some(self.near.started)
            } else {
                None
            };
            if let Some(since) = switch_at {
                self.pending = Some(Switch {
                    to: Method::Rodas,
                    since,
                    to_stiff: true,
                    h_max: f64::INFINITY,
                });
            }
        }
    }

    fn rejected(&mut self) {
        if self.stiff {
            self.implicit.rejected();
        } else {
            self.explicit.rejected();
        }
    }

    fn restart(&mut self) {
        self.explicit.restart();
        self.implicit.restart();
    }

    fn take_switch(&mut self) -> Option<Switch> {
        let switch = self.pending.take()?;
        let to_stiff = switch.to == Method::Rodas;
        if to_stiff && self.switches > 0 {
            // back to Rodas after a return to DOPRI5: the next return needs twice the evidence
            self.nonstiff_steps_needed = self.nonstiff_steps_needed.saturating_mul(2);
        }
        self.stiff = to_stiff;
        self.held = Run::default();
        self.near = Run::default();
        self.switches += 1;
        // a new Jacobian is due at the next Rodas step whatever came before
        self.implicit.restart();
        Some(switch)
    }

    fn add_counts(&self, stats: &mut Stats) {
        self.implicit.add_counts(stats);
        stats.method_switches += self.switches;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_return_to_rodas_doubles_the_evidence_the_next_return_to_dopri5_needs() {
        let mut a = AutoSwitch::<1>::new(&SolverOptions::default());
        let switch = |to| Switch {
            to,
            since: 0.0,
            to_stiff: to == Method::Rodas,
            h_max: f64::INFINITY,
        };
        let mut needed = Vec::new();
        for to in [
            Method::Rodas,
            Method::Dp5,
            Method::Rodas,
            Method::Dp5,
            Method::Rodas,
        ] {
            a.pending = Some(switch(to));
            assert_eq!(a.take_switch().map(|s| s.to), Some(to));
            assert_eq!(a.current(), to);
            needed.push(a.nonstiff_steps_needed);
        }
        assert_eq!(needed, [5, 5, 10, 10, 20]);
        assert_eq!(a.take_switch(), None);
    }

    #[test]
    fn a_long_run_near_the_stability_limit_switches_to_rodas() {
        let a_run_of = |h_lambda: f64, steps: u32| {
            let mut a = AutoSwitch::<1>::new(&SolverOptions::default());
            a.h_lambda = Some(h_lambda);
            for _ in 0..steps {
                a.accepted();
            }
            a.take_switch().map(|s| s.to)
        };
        // under the threshold of the quick switch, above a radian a step
        let near = 0.5 * STABILITY_BOUNDARY;
        assert!(near < THRESHOLD && near > PATIENT_FRACTION * STABILITY_BOUNDARY);
        assert_eq!(a_run_of(near, PATIENT_STEPS - 1), None);
        assert_eq!(a_run_of(near, PATIENT_STEPS), Some(Method::Rodas));
        // an accuracy-bound run never switches, however long
        assert_eq!(
            a_run_of(0.25 * STABILITY_BOUNDARY, 10 * PATIENT_STEPS),
            None
        );
        // and the quick switch still takes its ten steps
        assert_eq!(
            a_run_of(THRESHOLD * 1.01, TO_STIFF_STEPS),
            Some(Method::Rodas)
        );
    }

    #[test]
    fn a_switch_needs_its_steps_in_a_row() {
        let mut run = Run::default();
        for i in 0..TO_STIFF_STEPS - 1 {
            assert!(!run.count(i as f64, true, TO_STIFF_STEPS, 0));
        }
        // one step off the limit starts the count again
        assert!(!run.count(50.0, false, TO_STIFF_STEPS, 0));
        for i in 0..TO_STIFF_STEPS {
            let t = 100.0 + i as f64;
            assert_eq!(
                run.count(t, true, TO_STIFF_STEPS, 0),
                i + 1 == TO_STIFF_STEPS
            );
        }
        assert_eq!(run.started, 100.0);
    }
}
