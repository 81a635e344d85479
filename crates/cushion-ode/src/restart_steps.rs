//! The first step after an event that restarted the integration.
//!
//! After a restart the loop takes the smaller of Hairer's initial step, from the slopes at the
//! restart point, and the last step before it. Leaving a stiff contact that caps the first
//! step in free flight at a contact step, a hundred times too short, and the controller's
//! largest growth (10 a step) then takes two or three short steps to reach the flight's size.
//! Where the same event recurs, as when a tool bounces on a steel stop 150 times, the first
//! step after it the last time says how long it may be: its size grown as its own error allows
//! (as the controller grows a step), kept below half the smallest first attempt ever rejected
//! after that event, so that a guess that failed is not tried again each time.
//!
//! Only an event whose first step was accepted at the first attempt is learned. Where it was
//! rejected, the event is a discontinuity the error estimate does not see well: a Hertzian
//! contact that has just begun, whose force grows like `delta^1.5` from zero, leaves a local
//! error of order `h^2.5` that the embedded estimate understates. There the step that passed
//! the estimate after the last onset, tried first at the next one, let a bouncing ball's
//! rebound speed drift by 1.2e-4 over eight bounces at rtol 1e-6, where the rejected attempt and
//! its retry (`retry_after_discontinuity`) keep it within 2.1e-6; such an event starts from
//! Hairer's selection each time.
//!
//! A step is learned from once the loop keeps it: a first step that the loop takes back after
//! accepting it (a kinked crossing found inside it, a jump past the stability boundary:
//! `solve/attempt.rs`, `take_back`) is reported as rejected, as the run's statistics count it. And
//! only the part the run kept is learned: a first step that the next event cut short is
//! learned as its length up to that event. Learned whole, an attempt of which the run kept a
//! picosecond was tried again at every recurrence, grown each time, and the same event found a
//! picosecond into it, until the step limit (under Rodas, on an event function that sits at
//! zero to within rounding: `cushion-model/tests/model/recurring_events.rs`).
//!
//! Guarded by `tests/integrator/stiff_contact.rs::a_recurring_contact_reuses_its_first_step`.

use crate::system::MAX_EVENTS;

/// The largest growth from the first step after an event to the first step tried after it the
/// next time: the controller's largest step-to-step growth (DOPRI5's).
const MAX_GROWTH: f64 = 10.0;

/// A first step after an event is kept to this share of the smallest first attempt rejected
/// after it.
const BELOW_REJECTED: f64 = 0.5;

/// Per event function and direction (index `rising as usize`): the first step to try after it,
/// and the smallest first attempt rejected after it.
pub(crate) struct RestartSteps {
    next_first: [[f64; 2]; MAX_EVENTS],
    rejected_first: [[f64; 2]; MAX_EVENTS],
    /// The event the current restart followed, until a step is accepted.
    learning: Option<(usize, bool)>,
    /// An attempt since that restart was rejected.
    rejected: bool,
}

impl RestartSteps {
    pub(crate) fn new() -> Self {
        RestartSteps {
            next_first: [[f64::NAN; 2]; MAX_EVENTS],
            rejected_first: [[f64::INFINITY; 2]; MAX_EVENTS],
            learning: None,
            rejected: false,
        }
    }

    /// A restart after the event `index` (`rising` or falling through zero). Returns the step
    /// to try first, if the same event restarted the run before.
    pub(crate) fn restart(&mut self, event: Option<(usize, bool)>) -> Option<f64> {
        self.learning = event.filter(|&(i, _)| i < MAX_EVENTS);
        self.rejected = false;
        let (i, rising) = self.learning?;
        let h = self.next_first[i][rising as usize];
        h.is_finite().then_some(h)
    }

    /// An attempt of size `h` was rejected.
    pub(crate) fn rejected(&mut self, h: f64) {
        if let Some((i, rising)) = self.learning {
            if !self.rejected {
                let r = &mut self.rejected_first[i][rising as usize];
                *r = r.min(h);
            }
            self.rejected = true;
        }
    }

    /// A step was accepted with the scaled error `err` (`None`: not estimated) and kept up to
    /// `h` after its start.
    /// If it is the first since the restart after an event: the step to try first after that
    /// event the next time, if the first attempt since the restart was accepted; else none
    /// (Hairer's selection again).
    pub(crate) fn accepted(&mut self, h: f64, err: Option<f64>, order: u32) {
        let Some((i, rising)) = self.learning.take() else {
            return;
        };
        let k = rising as usize;
        // (a step cut by an event at its very start kept nothing to learn from)
        if self.rejected || !(h > 0.0) {
            self.next_first[i][k] = f64::NAN;
            return;
        }
        let growth = err.map_or(1.0, |e| (0.9 / e).powf(1.0 / order as f64).min(MAX_GROWTH));
        // (NaN growth, from err = NaN, keeps h); never below the size just accepted
        let next = h * growth.max(1.0);
        self.next_first[i][k] = next.min(BELOW_REJECTED * self.rejected_first[i][k]).max(h);
    }
}

#[cfg(test)]
mod tests {
    use super::RestartSteps;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a / b - 1.0).abs() < 1e-14)
    }

    /// Learned after a first attempt accepted with error 1e-10: grown by the largest factor;
    /// after that guess is rejected, forgotten, and the next guess kept below half of it.
    #[test]
    fn a_first_step_is_learned_grown_forgotten_and_bounded() {
        let mut r = RestartSteps::new();
        let lift_off = Some((3, true));
        assert_eq!(r.restart(lift_off), None);
        r.accepted(1e-6, Some(1e-10), 5);
        // a step accepted with no restart before it teaches nothing
        r.accepted(1.0, Some(1e-10), 5);
        assert!(close(r.restart(lift_off), 1e-5));
        // another direction of the same function: nothing learned there yet
        assert_eq!(r.restart(Some((3, false))), None);
        r.accepted(2e-6, Some(0.5), 5);
        // err 0.5: grown by (0.9 / 0.5)^(1/5)
        let grown = 2e-6 * 1.8f64.powf(0.2);
        assert!(close(r.restart(Some((3, false))), grown));
        r.accepted(grown, Some(1.0), 5);
        // err 1: kept (never below a size that was accepted)
        assert!(close(r.restart(Some((3, false))), grown));
        // the guess after the lift-off is rejected and its retry accepted: forgotten
        let guess = r.restart(lift_off).unwrap();
        r.rejected(guess);
        r.accepted(4e-6, Some(1e-3), 5);
        assert_eq!(r.restart(lift_off), None);
        // learned again from a tiny error, but kept below half the rejected guess
        r.accepted(1e-6, Some(1e-12), 5);
        assert!(close(r.restart(lift_off), 0.5 * guess));
    }

    /// A first step taken back after it was accepted teaches nothing, and counts as the first
    /// attempt rejected: the retry is not learned, and later guesses stay below half of it.
    #[test]
    fn a_first_step_taken_back_is_not_learned() {
        let mut r = RestartSteps::new();
        let onset = Some((1, false));
        assert_eq!(r.restart(onset), None);
        r.accepted(1e-6, Some(1e-10), 5);
        assert!(close(r.restart(onset), 1e-5));
        // this restart's first step (the learned 1e-5) is accepted but taken back: the loop
        // reports it as rejected, and reports no acceptance
        r.rejected(1e-5);
        // its retry is accepted: a restart whose first attempt failed is not learned
        r.accepted(2e-6, Some(1e-10), 5);
        assert_eq!(r.restart(onset), None);
        // learned again later, but kept below half the step taken back
        r.accepted(1e-6, Some(1e-12), 5);
        assert!(close(r.restart(onset), 5e-6));
        // a step taken back that was not a restart's first changes nothing learned
        r.accepted(5e-6, Some(1e-10), 5);
        r.rejected(1e-4);
        r.accepted(5e-5, Some(1e-10), 5);
        assert!(close(r.restart(onset), 5e-6));
    }

    /// What a first step cut short by the next event teaches is the part the run kept (the loop
    /// passes that length), grown as the whole step's error allows; a step cut at its very
    /// start teaches nothing.
    #[test]
    fn a_first_step_cut_short_teaches_the_part_kept() {
        let mut r = RestartSteps::new();
        let release = Some((2, true));
        assert_eq!(r.restart(release), None);
        // a 13 ms attempt, accepted with err 0.97, kept up to 8e-13 s
        r.accepted(8e-13, Some(0.97), 4);
        let next = r.restart(release).unwrap();
        assert!((8e-13..1e-12).contains(&next), "{next:e}");
        r.accepted(0.0, Some(0.5), 4);
        assert_eq!(r.restart(release), None);
    }
}
