//! Hairer's stiffness test for DOPRI5: `h * |lambda|` estimated from two evaluations at
//! `t + h`; 15 steps in a row above [`THRESHOLD`] mean stiff; 6 non-stiff steps reset the count.
//!
//! The threshold is 0.9 of DOPRI5's stability boundary (2.976), not Hairer's 3.25. At the
//! stability limit the step controller settles where the error estimate, not the solution,
//! stops growing, and the estimate of `h |lambda|` there sits a little under the boundary
//! (0.95-0.97 of it, for many steps in a row) or wanders about it, so a threshold 2 % under
//! the boundary can miss a run that steps at its stability limit for good
//! (`tests::fires_on_a_plateau_just_under_the_boundary`; in `cushion-model`,
//! `tests/model/statuses.rs::a_run_held_at_the_stability_limit_is_flagged_stiff`, a run held there by
//! the orifice's damping). 0.9 of the boundary is what OrdinaryDiffEq's `AutoSwitch` uses
//! (`stifftol = 9/10` of the method's stability size). A step bound by the accuracy of a fast
//! mode keeps its `h |lambda|` below it: that mode's error would exceed the tolerance first.

use crate::{Matrix, State};

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

/// Whether a step's dense output is stable, from the method's estimate `h_lambda` and its
/// dense output's stability boundary (infinite where it is stable wherever the step is:
/// [`crate::stepper::Stepper::dense_stability_boundary`]): below [`DENSE_MARGIN`] of the
/// boundary, and never where a finite boundary has no estimate.
pub fn dense_stable(h_lambda: Option<f64>, boundary: f64) -> bool {
    boundary.is_infinite() || h_lambda.is_some_and(|x| x <= DENSE_MARGIN * boundary)
}

/// The share of the dense output's stability boundary up to which [`h_lambda`] counts a step's
/// dense output as stable. The estimate is a quotient along one direction, the difference of
/// two states at `t + h`, and may fall well short of the fastest mode's `h |lambda|`; below
/// 0.9 the peaks of the design space under DOP853 at rtol 1e-6 were still 2.3e-4 off
/// (relative) in 8 of 16,384 runs, below 0.6 none by more than 3.5e-5, for 1.3 % more
/// evaluations than DOP853 took before any step was integrated again (`cushion-model`,
/// `peaks/top_step.rs`; `python3 -m lab.design_accuracy solver.method=dop853`).
pub const DENSE_MARGIN: f64 = 0.6;

/// The test's running state.
#[derive(Clone, Copy, Debug)]
pub struct StiffnessDetector {
    stiff_in_a_row: u32,
    non_stiff: u32,
    run_started: Option<f64>,
    /// The method's threshold ([`crate::stepper::Stepper::stiffness_threshold`]).
    threshold: f64,
    /// The steps in a row above [`PATIENT_FRACTION`] of the boundary.
    near: Run,
}

/// A run of accepted steps in a row towards a verdict (held near the stability limit; for
/// `auto`, a switch), which survives a few steps in a row that do not count.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Run {
    /// Steps that counted, the steps since the last that counted, and when the run began.
    pub(crate) in_a_row: u32,
    breaks: u32,
    pub(crate) started: f64,
}

impl Run {
    /// Count one accepted step from `t`; `true` when the run is `needed` steps long. A run
    /// survives up to `breaks_allowed` steps in a row that do not count (they add nothing).
    pub(crate) fn count(&mut self, t: f64, counts: bool, needed: u32, breaks_allowed: u32) -> bool {
        if !counts {
            self.breaks += 1;
            if self.breaks > breaks_allowed {
                self.in_a_row = 0;
            }
            return false;
        }
        self.breaks = 0;
        if self.in_a_row == 0 {
            self.started = t;
        }
        self.in_a_row += 1;
        self.in_a_row >= needed
    }
}

/// DOPRI5's threshold ([`THRESHOLD`]).
impl Default for StiffnessDetector {
    fn default() -> Self {
        Self::with_threshold(THRESHOLD)
    }
}

/// DOPRI5's stability boundary on the negative real axis: the `x` with `|R(-x)| = 1` for its
/// stability polynomial `R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24 + z^5/120 + z^6/600`.
pub const STABILITY_BOUNDARY: f64 = 3.306_567_892_634_946;

/// The share of a method's stability boundary that its stiffness threshold is (see the
/// module's doc).
pub const THRESHOLD_SHARE: f64 = 0.9;

/// Threshold on `h * |lambda|`: [`THRESHOLD_SHARE`] of [`STABILITY_BOUNDARY`] (see the
/// module's doc).
pub const THRESHOLD: f64 = THRESHOLD_SHARE * STABILITY_BOUNDARY;
/// Stiff steps in a row before the test fires.
pub const STIFF_STEPS: u32 = 15;
/// Non-stiff steps that reset the count.
pub const RESET_STEPS: u32 = 6;

/// Steps in a row with `h |lambda|` above [`PATIENT_FRACTION`] of the method's stability
/// boundary that mean its steps are held by stability, even where they stay under the test's
/// threshold. A mode that decays by a factor `e`, or turns by a radian, on every one of a
/// thousand steps carries nothing a tolerance resolves (DOPRI5 resolves an oscillation to
/// rtol 1e-6 at about a quarter radian a step), so only stability can hold the steps there.
/// A stiff mode through a nonlinear law holds the controller well inside the boundary: the
/// compressible liquid's orifice across its laminar transition kept DOPRI5 at `h |lambda|`
/// 1.6-1.7 for a million steps (`cushion-model/tests/model/auto.rs`). `auto` switches to Rodas on
/// such a run ([`crate::auto`]); under the other methods a run that reaches its step limit
/// inside one says so.
pub const PATIENT_STEPS: u32 = 1000;
/// The share of the stability boundary above which a step counts towards [`PATIENT_STEPS`]:
/// `h |lambda|` about 1 for DOPRI5.
pub const PATIENT_FRACTION: f64 = 0.3;
/// Steps in a row under that share that such a run survives (the controller oscillates at the
/// limit, and the estimate dips now and then).
pub const PATIENT_BREAKS: u32 = 2;

impl StiffnessDetector {
    /// For a method whose threshold on `h |lambda|` is `threshold` (0.9 of its stability
    /// boundary).
    pub fn with_threshold(threshold: f64) -> Self {
        StiffnessDetector {
            stiff_in_a_row: 0,
            non_stiff: 0,
            run_started: None,
            threshold,
            near: Run::default(),
        }
    }

    /// `h |lambda|` above which a step counts towards [`PATIENT_STEPS`].
    pub fn near_limit(&self) -> f64 {
        PATIENT_FRACTION / THRESHOLD_SHARE * self.threshold
    }

    /// The steps in a row held near the stability limit up to the last one observed, if they
    /// are [`PATIENT_STEPS`] or more.
    pub fn held_near_limit(&self) -> Option<u32> {
        (self.near.in_a_row >= PATIENT_STEPS).then_some(self.near.in_a_row)
    }

    /// The threshold on `h |lambda|`.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// Feed one accepted step that started at `t` with estimate `h_lambda`. Returns
    /// `Some(start)` the step the test fires, with the time its stiff run began.
    pub fn observe(&mut self, t: f64, h_lambda: f64) -> Option<f64> {
        let near = h_lambda > self.near_limit();
        self.near.count(t, near, PATIENT_STEPS, PATIENT_BREAKS);
        if h_lambda > self.threshold {
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

/// Power iterations of [`spectral_radius`]: the first [`WARM_UP`] turn the start vector
/// towards the dominant eigenvectors, the rest measure the growth.
const POWER_ITERATIONS: usize = 12;
const WARM_UP: usize = 4;

/// An estimate of the spectral radius of `jac` (the largest `|lambda|`), by power iteration
/// on `D^-1 J D` with `D = diag(scale)` (the components' tolerance scales: a similarity, so
/// the eigenvalues are those of `J`, while the states' units, metres beside pascals, no
/// longer decide the start). The growth `|B^m v| / |v|` over the last `m` iterations, taken
/// to the power `1/m`, converges to the spectral radius for a dominant real eigenvalue and
/// for a dominant complex pair alike (where the ratio of one iteration oscillates). A
/// transient of a non-normal matrix can only make it larger, which is the safe side for
/// deciding that an explicit method is stable. `0` for a nilpotent or zero `J`, infinite when
/// `J` is not finite.
pub fn spectral_radius<const N: usize>(jac: &Matrix<N>, scale: &State<N>) -> f64 {
    // a start vector that no structure of the problem makes orthogonal to an eigenvector
    let mut v = State::<N>::from_fn(|i, _| 1.0 / (1.0 + 0.618 * i as f64));
    v /= v.norm();
    let mut log_growth = 0.0;
    for k in 0..POWER_ITERATIONS {
        let mut u = v;
        for i in 0..N {
            u[i] *= scale[i];
        }
        let mut w = jac * u;
        for i in 0..N {
            w[i] /= scale[i];
        }
        let norm = w.norm();
        if norm == 0.0 {
            return 0.0;
        }
        if !norm.is_finite() {
            return f64::INFINITY;
        }
        if k >= WARM_UP {
            log_growth += norm.ln();
        }
        v = w / norm;
    }
    (log_growth / (POWER_ITERATIONS - WARM_UP) as f64).exp()
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
    fn a_thousand_steps_near_the_limit_are_told_apart_from_accuracy_bound_ones() {
        let near = 0.5 * STABILITY_BOUNDARY;
        let mut d = StiffnessDetector::default();
        for i in 0..PATIENT_STEPS - 1 {
            assert_eq!(d.observe(i as f64, near), None);
            assert_eq!(d.held_near_limit(), None);
        }
        // two dips do not break the run; the test itself never fires under its threshold
        d.observe(2000.0, 0.1);
        d.observe(2001.0, 0.1);
        assert_eq!(d.observe(2002.0, near), None);
        assert_eq!(d.held_near_limit(), Some(PATIENT_STEPS));
        // three do
        for i in 0..3 {
            d.observe(3000.0 + i as f64, 0.1);
        }
        assert_eq!(d.held_near_limit(), None);
        // an accuracy-bound run at a quarter of the boundary never counts
        let mut d = StiffnessDetector::default();
        for i in 0..10 * PATIENT_STEPS {
            d.observe(i as f64, 0.25 * STABILITY_BOUNDARY);
        }
        assert_eq!(d.held_near_limit(), None);
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

    #[test]
    fn spectral_radius_of_real_and_complex_spectra_whatever_the_units() {
        // a stiff spring-damper (eigenvalues -10 and -1e4, real) with states in units 1e6
        // apart, and an undamped oscillator (+-1e3 i), each within 20 %
        let scale = State::<3>::new(1e-9, 1e-3, 1.0);
        let mut j = Matrix::<3>::zeros();
        // x' = v, v' = -1e5 x - 10010 v: roots of s^2 + 10010 s + 1e5 = 0 are -10 and -1e4
        j[(0, 1)] = 1.0;
        j[(1, 0)] = -1e5;
        j[(1, 1)] = -10010.0;
        let rho = spectral_radius(&j, &scale);
        assert!((rho / 1e4 - 1.0).abs() < 0.2, "{rho}");
        let mut osc = Matrix::<3>::zeros();
        osc[(0, 1)] = 1.0;
        osc[(1, 0)] = -1e6;
        let rho = spectral_radius(&osc, &scale);
        assert!((rho / 1e3 - 1.0).abs() < 0.2, "{rho}");
        assert_eq!(spectral_radius(&Matrix::<3>::zeros(), &scale), 0.0);
    }
}
