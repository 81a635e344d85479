//! Whether an accepted step is kept or taken again from the same point, shorter; and the steps
//! held at the stiffness threshold after one was taken again for stability.
//!
//! An error estimate passes steps it should not in three cases, each taken again once:
//!
//! - a step that jumped past the method's stability boundary ([`GUARD_GROWTH`],
//!   [`crate::stepper::Stepper::stability_guard`]): DOP853's combined estimate can pass one
//!   where a stiff mode is at rest;
//! - a step whose dense output is not stable and in which the event scan found a crossing
//!   (`events.rs`, "Crossings on a dense output that is not stable"): taken again short enough
//!   for its dense output to be stable ([`REDO_STABLE`]);
//! - a step that found a kinked crossing well inside it (`events.rs`, "Kinked crossings"):
//!   taken again to end just past it.
//!
//! After either of the first two, the steps are held at the stiffness threshold from the latest
//! estimate of `|lambda|`: where the stiff mode is at rest no error estimate limits them, and
//! the controller's next step would jump past the boundary again and be taken again, every
//! other step (`cushion-model/tests/model/dop853_at_rest.rs`).

use crate::step_plan::LAND_PAST;
use crate::stepper::Stepper;
use crate::stiffness::DENSE_MARGIN;

/// An accepted step longer than this many times the controller's size for the step before,
/// with `h |lambda|` past the method's [`Stepper::stability_guard`], is taken again at the
/// stiffness threshold. Steps held by stability wander about the boundary with smaller
/// ratios: guarding every step past it cost DOP853 10 to 15 % more evaluations on the design
/// space, guarding the jumps 0.03 to 0.3 % (`docs/accuracy.md`, section 7).
pub(crate) const GUARD_GROWTH: f64 = 2.0;

/// A step taken again for a crossing on its unstable dense output aims this far inside the
/// dense output's stable range (`stiffness::DENSE_MARGIN` of its boundary), since `h |lambda|`
/// is estimated, not known.
pub(crate) const REDO_STABLE: f64 = 0.9;

/// What a method says of its stability, in `h |lambda|` (constants of the method).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stability {
    /// Past this, a step that jumped is taken again ([`Stepper::stability_guard`]).
    pub(crate) guard: f64,
    /// Steps held by stability are held here ([`Stepper::stiffness_threshold`]).
    pub(crate) threshold: f64,
    /// The dense output's stability boundary ([`Stepper::dense_stability_boundary`]).
    pub(crate) dense_bound: f64,
}

impl Stability {
    #[inline(always)]
    pub(crate) fn of<M: Stepper<N>, const N: usize>(method: &M) -> Self {
        Stability {
            guard: method.stability_guard(),
            threshold: method.stiffness_threshold(),
            dense_bound: method.dense_stability_boundary(),
        }
    }
}

/// The guard's state across a run: what the current attempt is a retake of, and the stiff
/// mode's `|lambda|` once a step was taken again for it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct StepGuard {
    /// The controller's size for the last step kept (before a forecast or a stop cut it). The
    /// run's first step has none before it, so past the boundary it counts as a jump (a run
    /// that starts at rest on a stiff stop passes its error test at any length there:
    /// `cushion-model/tests/model/dop853_at_rest.rs`).
    h_before: f64,
    /// The attempt is a step taken again at the stiffness threshold.
    for_stability: bool,
    /// The attempt is a step taken again for a crossing on an unstable dense output.
    for_dense_output: bool,
    /// The attempt is a step taken again to end just past a kinked crossing, which it keeps
    /// whatever it finds.
    for_kink: bool,
    /// `|lambda|` of the stiff mode, once a step was taken again for stability: the steps
    /// after are held at the stiffness threshold.
    held: Option<f64>,
}

impl StepGuard {
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// Whether a forecast crossing may shorten the next attempt: not a step taken again for
    /// its unstable dense output, which must be long enough to hold the crossing it found, not
    /// a sliver short of a forecast one.
    #[inline]
    pub(crate) fn allows_forecast(&self) -> bool {
        !self.for_dense_output
    }

    /// An accepted step of size `h` with the estimate `h_lambda` of `h |lambda|`: the size to
    /// take it again with, at the stiffness threshold, if it jumped past the method's
    /// stability boundary and is not itself such a retake ([`GUARD_GROWTH`]).
    #[inline]
    pub(crate) fn jumped(
        &mut self,
        s: &Stability,
        adaptive: bool,
        h: f64,
        h_lambda: Option<f64>,
    ) -> Option<f64> {
        if let Some(x) = h_lambda.filter(|&x| {
            adaptive && !self.for_stability && x > s.guard && h > GUARD_GROWTH * self.h_before
        }) {
            self.held = Some(x / h);
            self.for_stability = true;
            return Some(h * (s.threshold / x));
        }
        self.for_stability = false;
        None
    }

    /// The estimate `h_lambda` of an accepted step if its dense output is not stable and the
    /// step may be taken again for a crossing found on it (not itself such a retake).
    #[inline]
    pub(crate) fn unstable_at(
        &self,
        adaptive: bool,
        h_lambda: Option<f64>,
        dense_stable: bool,
    ) -> Option<f64> {
        h_lambda.filter(|_| adaptive && !self.for_dense_output && !dense_stable)
    }

    /// Whether the event scan may ask for the step again for a kinked crossing inside it: for
    /// a method that lands on kinks, and not a step already taken again for one.
    #[inline]
    pub(crate) fn redoes_kinks(&self, lands_on_kinks: bool) -> bool {
        lands_on_kinks && !self.for_kink
    }

    /// The event scan asked for the accepted step from `t` of size `h` again, for a crossing
    /// at `t_cross`: the size to take it again with. On an unstable dense output (`unstable_at`,
    /// the step's `h |lambda|`), short enough for it to be stable; else (a kink of `f` well
    /// inside the step, which its estimate did not see) to end just past the crossing.
    #[inline]
    pub(crate) fn retake(
        &mut self,
        s: &Stability,
        t: f64,
        h: f64,
        t_cross: f64,
        unstable_at: Option<f64>,
    ) -> f64 {
        if let Some(x) = unstable_at {
            self.held = Some(x / h);
            self.for_dense_output = true;
            h * (REDO_STABLE * DENSE_MARGIN * s.dense_bound / x)
        } else {
            self.for_kink = true;
            (t_cross - t) * (1.0 + LAND_PAST)
        }
    }

    /// The run keeps the step of size `h` (the controller's size for it `h_ctrl`, its estimate
    /// `h_lambda`), and the controller proposes `h_new`: the size to plan the next step from,
    /// at most the stiffness threshold once steps are held.
    #[inline]
    pub(crate) fn kept(
        &mut self,
        s: &Stability,
        h: f64,
        h_ctrl: f64,
        h_lambda: Option<f64>,
        h_new: f64,
    ) -> f64 {
        self.for_kink = false;
        self.for_dense_output = false;
        self.h_before = h_ctrl;
        match self.held.as_mut() {
            Some(lambda) => {
                if let Some(x) = h_lambda {
                    *lambda = x / h;
                }
                h_new.min(s.threshold / *lambda)
            }
            None => h_new,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: Stability = Stability {
        guard: 6.0,
        threshold: 3.0,
        dense_bound: 5.0,
    };

    #[test]
    fn a_jump_past_the_boundary_is_taken_again_once_then_held() {
        let mut g = StepGuard::new();
        // the run's first step counts as a jump
        assert_eq!(g.jumped(&S, true, 1.0, Some(12.0)), Some(0.25));
        // its retake is kept whatever its estimate, and holds the steps after
        assert_eq!(g.jumped(&S, true, 0.25, Some(12.0)), None);
        assert_eq!(g.kept(&S, 0.25, 0.25, Some(1.5), 10.0), 0.5);
        // held by the latest estimate of |lambda| (here 4 per unit of time)
        assert_eq!(g.jumped(&S, true, 0.5, Some(2.0)), None);
        assert_eq!(g.kept(&S, 0.5, 0.5, Some(2.0), 10.0), 0.75);
        // a step that did not jump (not twice the one before) is left alone
        assert_eq!(g.jumped(&S, true, 0.9, Some(7.0)), None);
        // without an estimate, still held by the last one
        assert_eq!(g.kept(&S, 0.9, 0.9, None, 10.0), 0.75);
        // a fixed step is never taken again
        let mut g = StepGuard::new();
        assert_eq!(g.jumped(&S, false, 1.0, Some(12.0)), None);
        assert_eq!(g.kept(&S, 1.0, 1.0, Some(12.0), 1.0), 1.0);
    }

    #[test]
    fn a_crossing_on_an_unstable_dense_output_takes_the_step_again_once() {
        let mut g = StepGuard::new();
        assert!(g.allows_forecast());
        // stable: nothing to redo
        assert_eq!(g.unstable_at(true, Some(4.0), true), None);
        let x = g.unstable_at(true, Some(8.0), false);
        assert_eq!(x, Some(8.0));
        let h = g.retake(&S, 0.0, 2.0, 1.0, x);
        assert_eq!(h, 2.0 * (REDO_STABLE * DENSE_MARGIN * 5.0 / 8.0));
        // the retake is not shortened by a forecast, and not taken again for its output
        assert!(!g.allows_forecast());
        assert_eq!(g.unstable_at(true, Some(8.0), false), None);
        // once kept, the next step may be; the steps are held from the retake's estimate
        assert_eq!(g.kept(&S, h, h, Some(0.5 * h), 10.0), 6.0);
        assert!(g.allows_forecast());
        assert_eq!(g.unstable_at(true, Some(8.0), false), Some(8.0));
    }

    /// The loop's side: `tests/integrator/stiff_contact.rs::a_lift_off_inside_a_step_is_taken_again`.
    #[test]
    fn a_kinked_crossing_inside_the_step_takes_it_again_just_past_the_crossing() {
        let mut g = StepGuard::new();
        assert!(g.redoes_kinks(true));
        assert!(!g.redoes_kinks(false));
        let h = g.retake(&S, 1.0, 1.0, 1.5, None);
        assert_eq!(h, 0.5 * (1.0 + LAND_PAST));
        // the retake keeps whatever it finds, and holds nothing
        assert!(!g.redoes_kinks(true));
        assert!(g.allows_forecast());
        assert_eq!(g.kept(&S, h, h, Some(2.9), 10.0), 10.0);
        assert!(g.redoes_kinks(true));
    }
}
