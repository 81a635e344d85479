//! One attempt and its judgement: the step, its error against the tolerance, the method's
//! completion of an accepted step; taking an accepted step back; Hairer's stiffness test.

use super::{End, Integration, SinceRestart};
use crate::controller::{retry_after_discontinuity, Controller};
use crate::observer::Observer;
use crate::options::StiffnessAction;
use crate::solution::Status;
use crate::step_guard::Stability;
use crate::stepper::{Attempt, Counted, StepFailure, Stepper};
use crate::stiffness::StiffnessDetector;
use crate::system::OdeSystem;

/// Whether every number of an attempt is finite.
#[inline]
fn is_finite<const N: usize>(a: &Attempt<N>) -> bool {
    a.y1.iter().all(|v| v.is_finite())
        && a.f1.is_none_or(|f| f.iter().all(|v| v.is_finite()))
        && a.err.is_none_or(|e| e.iter().all(|v| v.is_finite()))
        && a.err_low.is_none_or(|e| e.iter().all(|v| v.is_finite()))
}

/// What became of one attempted step.
pub(super) enum Tried {
    /// Accepted (and completed; the attempt is where the loop keeps it), with the step size
    /// the controller proposes next and the scaled error it was accepted with (`None`: not
    /// estimated), which the restart steps learn from once the loop keeps the step.
    Accepted(f64, Option<f64>),
    /// Rejected, or failed before its error estimate: try again with this size.
    Retry(f64),
    /// The run ends here.
    End(Status, String),
}

impl<S: OdeSystem<N>, O: Observer<S, N>, const N: usize> Integration<'_, S, O, N> {
    /// Hairer's estimate of `h |lambda|` for the accepted attempt of size `h`, for the
    /// stiffness test and for whether its dense output is stable (DOP853's is not near its
    /// boundary); not asked for where neither needs it.
    #[inline(always)]
    pub(super) fn h_lambda<M: Stepper<N>>(
        &self,
        stepper: &M,
        stability: &Stability,
        h: f64,
        attempt: &Attempt<N>,
    ) -> Option<f64> {
        if self.opts.stiffness != StiffnessAction::Off || stability.dense_bound.is_finite() {
            stepper.stiffness_estimate(h, attempt)
        } else {
            None
        }
    }

    /// Attempt one step of size `h` from the current state and judge it by the error
    /// estimate (fixed-step methods accept every finite step).
    pub(super) fn attempt<M: Stepper<N>>(
        &mut self,
        stepper: &mut M,
        controller: &mut M::Controller,
        adaptive: bool,
        h: f64,
        attempt: &mut Attempt<N>,
    ) -> Tried {
        let (t, y, f0) = (self.t, self.y, self.f);
        let counted = Counted::new(&*self.sys);
        let outcome = stepper.step_into(&counted, t, &y, &f0, h, attempt);
        self.stats.rhs_evals += counted.evals();
        let failed = match outcome {
            Ok(()) if is_finite(attempt) => None,
            Ok(()) => Some(StepFailure::NonFinite),
            Err(failure) => Some(failure),
        };
        if let Some(failure) = failed {
            if !adaptive {
                let msg = match failure {
                    StepFailure::NonFinite => {
                        format!("non-finite state in the step from t = {t} (fixed step {h:e})")
                    }
                    other => format!("{other} in the step from t = {t} (fixed step {h:e})"),
                };
                return Tried::End(Status::NonFinite, msg);
            }
            self.stats.rejected += 1;
            if failure != StepFailure::NonFinite {
                self.stats.failed_solves += 1;
            }
            stepper.rejected();
            self.plan.rejected(h);
            return Tried::Retry(controller.after_failure(h, failure));
        }
        let mut h_new = h;
        let mut err_norm = None;
        if let Some(err) = &attempt.err {
            let en = match &attempt.err_low {
                None => self.weights.error_norm(err, &y, &attempt.y1),
                Some(err3) => {
                    let combined = self.weights.dop853_error_norm(err, err3, &y, &attempt.y1);
                    // DOP853's combined estimate, `err5^2 / sqrt(err5^2 + 0.01 err3^2)`, is
                    // built for smooth solutions: for a force that sets in like `delta^1.5`
                    // where the step starts it gives 0.29 of the true error, its fifth-order
                    // estimate alone 1.46 (`lab/dop853_onset.py`). Such a step is judged
                    // by the larger (cushion-model's
                    // `tests/model/peaks.rs::dop853_after_a_gentle_contact_onset`).
                    if self.since_restart.on_kink {
                        combined.max(self.weights.error_norm(err, &y, &attempt.y1))
                    } else {
                        combined
                    }
                }
            };
            let (accepted, mut hn) = controller.next(en, h);
            if !accepted && self.since_restart.fresh {
                hn = hn.min(retry_after_discontinuity(en, h));
            }
            if !accepted {
                self.stats.rejected += 1;
                stepper.rejected();
                self.plan.rejected(h);
                return Tried::Retry(hn);
            }
            h_new = hn;
            err_norm = Some(en);
        }
        self.stats.steps += 1;
        self.since_restart = SinceRestart {
            fresh: false,
            on_kink: false,
        };
        // What the method evaluates for accepted steps only (DOP853: f(y1), dense stages).
        let counted = Counted::new(&*self.sys);
        let completed = stepper.complete(&counted, t, &y, h, attempt);
        self.stats.rhs_evals += counted.evals();
        stepper.accepted();
        if completed && !is_finite(attempt) {
            self.t = t + h;
            self.y = attempt.y1;
            return Tried::End(
                Status::NonFinite,
                format!("f is not finite at the accepted state at t = {}", t + h),
            );
        }
        Tried::Accepted(h_new, err_norm)
    }

    /// The step just accepted is not kept but taken again from the same point
    /// (`step_guard.rs`): it counts as rejected, and where the run stood since the last
    /// restart is set back to `since_restart`, as it was before the step, so that the step
    /// taken again is judged as the first after the restart if this one was; for the restart
    /// steps, the attempt of size `h` was rejected.
    pub(super) fn take_back(&mut self, since_restart: SinceRestart, h: f64) {
        self.stats.steps -= 1;
        self.stats.rejected += 1;
        self.since_restart = since_restart;
        self.plan.rejected(h);
    }

    /// Hairer's stiffness test on an accepted step from `t` of size `h`, with the method's
    /// estimate `h_lambda` of `h |lambda|`; the run's end when the options say to stop on
    /// stiffness.
    pub(super) fn observe_stiffness(
        &mut self,
        stiffness: &mut StiffnessDetector,
        t: f64,
        h: f64,
        h_lambda: Option<f64>,
        attempt: &Attempt<N>,
    ) -> Option<End> {
        if self.opts.stiffness == StiffnessAction::Off {
            return None;
        }
        let since = stiffness.observe(t, h_lambda?)?;
        if !self.stats.stiff {
            self.stats.stiff = true;
            self.stats.stiff_since = Some(since);
        }
        if self.opts.stiffness != StiffnessAction::Stop {
            return None;
        }
        self.t = t + h;
        self.y = attempt.y1;
        let msg = format!(
            "the problem is stiff since t = {since} (h*lambda > {:.3} for {} steps)",
            stiffness.threshold(),
            crate::stiffness::STIFF_STEPS
        );
        Some((Status::Stiff, msg))
    }
}
