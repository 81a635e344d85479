//! Hairer's stiffness test for DOPRI5: `h * |lambda|` estimated from two evaluations at
//! `t + h`; 15 steps in a row above 3.25 mean stiff; 6 non-stiff steps reset the count.

use crate::State;

/// Hairer's estimate `h |lambda| = h ||f(y1) - f(z)|| / ||y1 - z||` from the step's end `y1`
/// and the last stage's input `z`, both at `t + h`; `None` when they coincide.
pub fn h_lambda<const N: usize>(
    h: f64,
    y1: &State<N>,
    f1: &State<N>,
    z: &State<N>,
    fz: &State<N>,
) -> Option<f64> {
    let num = (f1 - fz).norm_squared();
    let den = (y1 - z).norm_squared();
    if den > 0.0 {
        Some(h.abs() * (num / den).sqrt())
    } else {
        None
    }
}

/// The test's running state.
#[derive(Clone, Copy, Debug, Default)]
pub struct StiffnessDetector {
    stiff_in_a_row: u32,
    non_stiff: u32,
    run_started: Option<f64>,
}

/// Threshold on `h * |lambda|` (DOPRI5's stability boundary along the negative axis is ~3.3).
pub const THRESHOLD: f64 = 3.25;
/// Stiff steps in a row before the test fires.
pub const STIFF_STEPS: u32 = 15;
/// Non-stiff steps that reset the count.
pub const RESET_STEPS: u32 = 6;

impl StiffnessDetector {
    /// Feed one accepted step that started at `t` with estimate `h_lambda`. Returns
    /// `Some(start)` the step the test fires, with the time its stiff run began.
    pub fn observe(&mut self, t: f64, h_lambda: f64) -> Option<f64> {
        if h_lambda > THRESHOLD {
            self.non_stiff = 0;
            if self.stiff_in_a_row == 0 {
                self.run_started = Some(t);
            }
            self.stiff_in_a_row += 1;
            if self.stiff_in_a_row == STIFF_STEPS {
                return self.run_started;
            }
        } else {
            self.non_stiff += 1;
            if self.non_stiff == RESET_STEPS {
                self.stiff_in_a_row = 0;
                self.run_started = None;
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fires_on_the_fifteenth_stiff_step_with_the_run_start() {
        let mut d = StiffnessDetector::default();
        for i in 0..14 {
            assert_eq!(d.observe(i as f64, 3.3), None);
        }
        assert_eq!(d.observe(14.0, 3.3), Some(0.0));
    }

    #[test]
    fn six_non_stiff_steps_reset_the_count() {
        let mut d = StiffnessDetector::default();
        for i in 0..10 {
            d.observe(i as f64, 4.0);
        }
        for i in 10..16 {
            d.observe(i as f64, 1.0);
        }
        for i in 16..30 {
            assert_eq!(d.observe(i as f64, 4.0), None, "step {i}");
        }
        assert_eq!(d.observe(30.0, 4.0), Some(16.0));
    }

    #[test]
    fn fewer_than_six_non_stiff_steps_do_not_reset() {
        let mut d = StiffnessDetector::default();
        for i in 0..10 {
            d.observe(i as f64, 4.0);
        }
        for i in 10..15 {
            d.observe(i as f64, 1.0);
        }
        for i in 15..19 {
            assert_eq!(d.observe(i as f64, 4.0), None);
        }
        assert_eq!(d.observe(19.0, 4.0), Some(0.0));
    }
}
