//! Hairer's stiffness test for DOPRI5: `h * |lambda|` estimated from two evaluations at
//! `t + h`; 15 steps in a row above [`THRESHOLD`] mean stiff; 6 non-stiff steps reset the count.
//!
//! The threshold is 0.9 of DOPRI5's stability boundary (2.976), not Hairer's 3.25. At the
//! stability limit the step controller settles where the error estimate, not the solution,
//! stops growing, and the estimate of `h |lambda|` there sits a little under the boundary
//! (0.95-0.97 of it, for many steps in a row) or wanders about it, so a threshold 2 % under
//! the boundary can miss a run that steps at its stability limit for good
//! (`tests::fires_on_a_plateau_just_under_the_boundary`; in `cushion-model`,
//! `tests/runs.rs::a_run_held_at_the_stability_limit_is_flagged_stiff`, a run held there by
//! the orifice's damping). 0.9 of the boundary is what OrdinaryDiffEq's `AutoSwitch` uses
//! (`stifftol = 9/10` of the method's stability size). A step bound by the accuracy of a fast
//! mode keeps its `h |lambda|` below it: that mode's error would exceed the tolerance first.

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

/// DOPRI5's stability boundary on the negative real axis: the `x` with `|R(-x)| = 1` for its
/// stability polynomial `R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24 + z^5/120 + z^6/600`.
pub const STABILITY_BOUNDARY: f64 = 3.306_567_892_634_946;

/// Threshold on `h * |lambda|`: 0.9 of [`STABILITY_BOUNDARY`] (see the module's doc).
pub const THRESHOLD: f64 = 0.9 * STABILITY_BOUNDARY;
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
    fn the_boundary_is_the_root_of_the_stability_polynomial() {
        let r = |z: f64| {
            1.0 + z
                + z * z / 2.0
                + z.powi(3) / 6.0
                + z.powi(4) / 24.0
                + z.powi(5) / 120.0
                + z.powi(6) / 600.0
        };
        assert!((r(-STABILITY_BOUNDARY).abs() - 1.0).abs() < 1e-13);
        // stable just inside, unstable just outside
        assert!(r(-STABILITY_BOUNDARY + 1e-6).abs() < 1.0);
        assert!(r(-STABILITY_BOUNDARY - 1e-6).abs() > 1.0);
        assert!((THRESHOLD - 2.9759).abs() < 1e-4);
    }

    #[test]
    fn fires_on_a_plateau_just_under_the_boundary() {
        // the estimates of a run held at its stability limit (3.15-3.20): below Hairer's 3.25
        let mut d = StiffnessDetector::default();
        for i in 0..14 {
            assert_eq!(d.observe(i as f64, 3.15 + 0.003 * i as f64), None);
        }
        assert_eq!(d.observe(14.0, 3.2), Some(0.0));
        // an accuracy-bound step's estimate never counts
        let mut d = StiffnessDetector::default();
        for i in 0..100 {
            assert_eq!(d.observe(i as f64, 2.9), None);
        }
    }

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
