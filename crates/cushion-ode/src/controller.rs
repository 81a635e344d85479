//! Step-size control: each method brings the controller that suits it
//! ([`crate::stepper::Stepper::controller`]): Hairer's PI controller for DOPRI5
//! ([`PiController`]), the predictive controller of Hairer's RODAS for the Rosenbrock method
//! ([`PredictiveController`]); and Hairer's initial step selection ([`initial_step`]).

use crate::failure::StepFailure;

/// What the integration loop asks of a step-size controller.
pub trait Controller {
    /// Given the scaled error norm `err` of a step of size `h`, say whether it is accepted and
    /// which step size comes next.
    fn next(&mut self, err: f64, h: f64) -> (bool, f64);
    /// An attempt of size `h` failed before it had an error estimate: the size to retry with.
    fn after_failure(&mut self, h: f64, failure: StepFailure) -> f64;
    /// Forget the history (after a handler changed the state or the regime).
    fn reset(&mut self);
}

/// `ln(1e-4)`: Hairer's floor and starting value of `facold`.
const LN_1E_4: f64 = -9.210_340_371_976_184;

/// PI controller (Hairer's DOPRI5: `fac = err^(0.2 - 0.75 beta) / facold^beta`, safety 0.9,
/// ratio within [0.2, 10], no growth right after a rejection).
#[derive(Clone, Copy, Debug)]
pub struct PiController {
    pub safety: f64,
    pub beta: f64,
    pub min_ratio: f64,
    pub max_ratio: f64,
    /// Exponent `1/order - 0.75 beta`.
    expo: f64,
    /// `ln(facold)`: Hairer's `facold^beta` is `exp(beta * ln_facold)`. Working in logarithms
    /// costs one `ln` and one `exp` a step instead of two `pow`.
    ln_facold: f64,
    last_rejected: bool,
}

impl PiController {
    /// For an embedded pair whose lower order is `order - 1` (`order` 5 for DOPRI5).
    pub fn new(order: u32, safety: f64, beta: f64, min_ratio: f64, max_ratio: f64) -> Self {
        PiController {
            safety,
            beta,
            min_ratio,
            max_ratio,
            expo: 1.0 / order as f64 - 0.75 * beta,
            ln_facold: LN_1E_4,
            last_rejected: false,
        }
    }

    /// Hairer's DOP853 (the code's defaults): `beta = 0`, safety 0.9, `fac1 = 0.333` and
    /// `fac2 = 6` (so `h_new / h` within `[0.333, 6]`), exponent `expo1 = 1/8 - 0.2 beta`
    /// (DOPRI5's is `1/5 - 0.75 beta`).
    pub fn dop853() -> Self {
        let beta = 0.0;
        PiController {
            safety: 0.9,
            beta,
            min_ratio: 0.333,
            max_ratio: 6.0,
            expo: 1.0 / 8.0 - 0.2 * beta,
            ln_facold: LN_1E_4,
            last_rejected: false,
        }
    }

    /// Forget the history (after an event changed the state).
    pub fn reset(&mut self) {
        self.ln_facold = LN_1E_4;
        self.last_rejected = false;
    }

    /// Given the scaled error norm `err` of a step of size `h`, say whether it is accepted and
    /// which step size comes next.
    pub fn next(&mut self, err: f64, h: f64) -> (bool, f64) {
        // err = 0 gives ln = -inf and fac = 0: clamped to the largest growth, as with pow.
        let ln_err = err.ln();
        if err <= 1.0 {
            // fac = err^expo / facold^beta
            let fac = (self.expo * ln_err - self.beta * self.ln_facold).exp();
            let fac = (fac / self.safety).clamp(1.0 / self.max_ratio, 1.0 / self.min_ratio);
            let mut h_new = h / fac;
            self.ln_facold = ln_err.max(LN_1E_4);
            if self.last_rejected {
                h_new = h_new.min(h);
            }
            self.last_rejected = false;
            (true, h_new)
        } else {
            self.last_rejected = true;
            let fac11 = (self.expo * ln_err).exp();
            (false, h / (fac11 / self.safety).min(1.0 / self.min_ratio))
        }
    }

    /// A step with a non-finite stage: reject it and shrink by the largest allowed factor.
    pub fn reject_non_finite(&mut self, h: f64) -> f64 {
        self.last_rejected = true;
        h * self.min_ratio
    }
}

impl Controller for PiController {
    #[inline]
    fn next(&mut self, err: f64, h: f64) -> (bool, f64) {
        PiController::next(self, err, h)
    }

    /// Every failure is a non-finite stage for the explicit methods: the largest shrink.
    #[inline]
    fn after_failure(&mut self, h: f64, _failure: StepFailure) -> f64 {
        self.reject_non_finite(h)
    }

    #[inline]
    fn reset(&mut self) {
        PiController::reset(self)
    }
}

/// The controller of Hairer's RODAS (Hairer & Wanner, *Solving ODEs II*, Sec. IV.8 and VI.4;
/// the code RODAS): the standard controller `h_new = h / fac`, `fac = err^(1/q) / safety`
/// (`q` = 4, the order of the propagated solution, so that `err ~ h^q`), and on accepted
/// steps Gustafsson's predictive modification (K. Gustafsson, "Control-theoretic techniques
/// for stepsize selection in implicit Runge-Kutta methods", ACM TOMS 20 (1994) 496-517):
/// `fac_pred = (h_acc / h) (err^2 / err_acc)^(1/q) / safety` from the previous accepted step
/// `h_acc`, `err_acc = max(err, 1e-2)`, and the smaller of the two steps is taken. It reduces
/// the step before the error does, where the error of an implicit method grows quickly
/// (a fast transient starting, a step held at a stiff component's accuracy limit), and so
/// saves rejections, each of which costs a factorization. The ratio `h_new / h` stays within
/// `[min_ratio, max_ratio]` (RODAS: 0.2 and 6), with no growth on the step right after a
/// rejection; a singular matrix halves the step (as RODAS does), a non-finite stage shrinks it
/// by `min_ratio`.
#[derive(Clone, Copy, Debug)]
pub struct PredictiveController {
    pub safety: f64,
    pub min_ratio: f64,
    pub max_ratio: f64,
    /// `1 / q`.
    expo: f64,
    /// The last accepted step and its error (floored at 1e-2), once there is one.
    h_acc: f64,
    err_acc: f64,
    has_history: bool,
    last_rejected: bool,
}

impl PredictiveController {
    /// For a method whose error estimate is `O(h^order)`.
    pub fn new(order: u32, safety: f64, min_ratio: f64, max_ratio: f64) -> Self {
        PredictiveController {
            safety,
            min_ratio,
            max_ratio,
            expo: 1.0 / order as f64,
            h_acc: 0.0,
            err_acc: 0.0,
            has_history: false,
            last_rejected: false,
        }
    }

    /// RODAS's settings for its order-4 method: safety 0.9, ratio within `[0.2, 6]`.
    pub fn rodas() -> Self {
        Self::new(4, 0.9, 0.2, 6.0)
    }

    #[inline]
    fn clamp_fac(&self, fac: f64) -> f64 {
        fac.clamp(1.0 / self.max_ratio, 1.0 / self.min_ratio)
    }
}

impl Controller for PredictiveController {
    fn next(&mut self, err: f64, h: f64) -> (bool, f64) {
        let mut fac = self.clamp_fac(err.powf(self.expo) / self.safety);
        if err <= 1.0 {
            if self.has_history {
                let pred =
                    (self.h_acc / h) * (err * err / self.err_acc).powf(self.expo) / self.safety;
                fac = fac.max(self.clamp_fac(pred));
            }
            self.has_history = true;
            self.h_acc = h;
            self.err_acc = err.max(1e-2);
            let mut h_new = h / fac;
            if self.last_rejected {
                h_new = h_new.min(h);
            }
            self.last_rejected = false;
            (true, h_new)
        } else {
            self.last_rejected = true;
            (false, h / fac)
        }
    }

    fn after_failure(&mut self, h: f64, failure: StepFailure) -> f64 {
        self.last_rejected = true;
        match failure {
            StepFailure::SingularMatrix => 0.5 * h,
            StepFailure::NonFinite => h * self.min_ratio,
        }
    }

    fn reset(&mut self) {
        self.has_history = false;
        self.last_rejected = false;
    }
}

/// The error's order in `h` assumed for the first attempt after a discontinuity: a force
/// that sets in like a Hertzian contact's, `delta^1.5`, leaves a local error in the velocity
/// of order `h^2.5` whatever the method's order.
const ORDER_AFTER_DISCONTINUITY: f64 = 2.5;

/// The largest shrink of one such retry.
const MIN_RATIO_AFTER_DISCONTINUITY: f64 = 0.02;

/// The size to retry with after the first attempt since a restart (an event or a time stop
/// that changed the regime) was rejected with the scaled error `err > 1`. Right
/// after a discontinuity the error grows with `h` like a low power, not like the method's
/// order, so the controller's own retry (`err^(1/5)` for DOPRI5, at most a factor 5 or 3)
/// would be rejected again several times over: `h (0.9 / err)^(1/2.5)`, at most 50 times
/// shorter. The loop takes the smaller of this and the controller's size, until a step is
/// accepted. Guarded by `tests/integrator/stiff_contact.rs::a_stiff_contact_costs_few_rejected_attempts`.
pub fn retry_after_discontinuity(err: f64, h: f64) -> f64 {
    h * (0.9 / err)
        .powf(1.0 / ORDER_AFTER_DISCONTINUITY)
        .max(MIN_RATIO_AFTER_DISCONTINUITY)
}

/// Hairer's initial step selection (`hinit` of DOPRI5). `f0 = f(t0, y0)`; `sq` scales a vector
/// by the tolerances and returns its sum of squares; `f_at(h, y) -> f(t0 + h, y)` costs one
/// evaluation. Returns a positive step no larger than `h_max`.
pub fn initial_step<const N: usize>(
    y0: &crate::State<N>,
    f0: &crate::State<N>,
    order: u32,
    h_max: f64,
    sq: impl Fn(&crate::State<N>, &crate::State<N>) -> f64,
    f_at: impl FnOnce(f64, &crate::State<N>) -> crate::State<N>,
) -> f64 {
    let dnf = sq(f0, y0);
    let dny = sq(y0, y0);
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    let y1 = y0 + f0 * h;
    let f1 = f_at(h, &y1);
    let der2 = (sq(&(f1 - f0), y0)).sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h.abs() * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / order as f64)
    };
    let h = (100.0 * h.abs()).min(h1).min(h_max);
    if h.is_finite() && h > 0.0 {
        h
    } else {
        h_max.min(1e-6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_hairers_pow_formula() {
        // Same numbers as fac11 = err^expo, fac = fac11 / facold^beta, clamped, h / fac.
        let mut c = PiController::new(5, 0.9, 0.04, 0.2, 10.0);
        let mut facold: f64 = 1e-4;
        let errs: [f64; 5] = [0.5, 0.01, 0.9, 0.3, 1e-3];
        let mut h = 1e-3;
        for &err in &errs {
            let fac = (err.powf(0.17) / facold.powf(0.04) / 0.9).clamp(0.1, 5.0);
            let expected = h / fac;
            let (ok, got) = c.next(err, h);
            assert!(ok);
            assert!(
                (got - expected).abs() <= 1e-14 * expected,
                "{got} vs {expected}"
            );
            facold = err.max(1e-4);
            h = got;
        }
        let (ok, got) = c.next(4.0, h);
        assert!(!ok);
        let expected = h / (4f64.powf(0.17) / 0.9).min(5.0_f64);
        assert!((got - expected).abs() <= 1e-14 * expected);
    }

    #[test]
    fn accepts_small_errors_and_grows_at_most_tenfold() {
        let mut c = PiController::new(5, 0.9, 0.04, 0.2, 10.0);
        let (ok, h) = c.next(1e-12, 1.0);
        assert!(ok);
        assert!((h - 10.0).abs() < 1e-12);
    }

    #[test]
    fn rejects_large_errors_and_does_not_grow_after_a_rejection() {
        let mut c = PiController::new(5, 0.9, 0.04, 0.2, 10.0);
        let (ok, h) = c.next(1e6, 1.0);
        assert!(!ok);
        assert!((h - 0.2).abs() < 1e-12, "shrinks by at most 5: {h}");
        let (ok, h2) = c.next(1e-12, h);
        assert!(ok);
        assert_eq!(h2, h, "no growth on the step after a rejection");
    }

    #[test]
    fn predictive_controller_matches_rodas_formulas() {
        let mut c = PredictiveController::rodas();
        // First accepted step: the standard controller alone.
        let (ok, h1) = Controller::next(&mut c, 0.5, 1e-3);
        assert!(ok);
        let want = 1e-3 / (0.5f64.powf(0.25) / 0.9).clamp(1.0 / 6.0, 5.0);
        assert!((h1 - want).abs() <= 1e-15 * want, "{h1} vs {want}");
        // Second: the larger reduction of the two (Gustafsson's prediction wins here, the
        // error having grown from 0.5 to 0.8).
        let (ok, h2) = Controller::next(&mut c, 0.8, h1);
        assert!(ok);
        let std = (0.8f64.powf(0.25) / 0.9).clamp(1.0 / 6.0, 5.0);
        let pred = ((1e-3 / h1) * (0.64f64 / 0.5).powf(0.25) / 0.9).clamp(1.0 / 6.0, 5.0);
        assert!(pred > std);
        let want = h1 / pred;
        assert!((h2 - want).abs() <= 1e-15 * want, "{h2} vs {want}");
        // Tiny errors: at most six-fold growth.
        let mut c = PredictiveController::rodas();
        let (_, h) = Controller::next(&mut c, 1e-12, 1.0);
        assert!((h - 6.0).abs() < 1e-12);
    }

    #[test]
    fn predictive_controller_rejects_shrinks_and_does_not_grow_after_a_rejection() {
        let mut c = PredictiveController::rodas();
        let (ok, h) = Controller::next(&mut c, 1e8, 1.0);
        assert!(!ok);
        assert!((h - 0.2).abs() < 1e-12, "at most five-fold: {h}");
        let (ok, h2) = Controller::next(&mut c, 1e-10, h);
        assert!(ok);
        assert_eq!(h2, h, "no growth right after a rejection");
        assert_eq!(c.after_failure(1.0, StepFailure::SingularMatrix), 0.5);
        assert!((c.after_failure(1.0, StepFailure::NonFinite) - 0.2).abs() < 1e-15);
    }

    #[test]
    fn dop853_controller_matches_the_codes_formula() {
        // fac = err^(1/8) / 0.9 within [1/6, 1/0.333]; no growth after a rejection
        let mut c = PiController::dop853();
        for (err, h) in [(0.5f64, 1e-2), (1e-3, 2e-2), (1e-12, 1.0), (0.99, 0.1)] {
            let (ok, got) = c.next(err, h);
            assert!(ok);
            let want = h / (err.powf(0.125) / 0.9).clamp(1.0 / 6.0, 1.0 / 0.333);
            assert!((got - want).abs() <= 1e-14 * want, "{got} vs {want}");
        }
        let (ok, h) = c.next(1e9, 1.0);
        assert!(!ok);
        assert!((h - 0.333).abs() < 1e-12, "shrinks by at most 1/0.333: {h}");
        let (ok, h2) = c.next(1e-12, h);
        assert!(ok);
        assert_eq!(h2, h);
        let (ok, h3) = c.next(10.0, 1.0);
        assert!(!ok);
        assert!((h3 - 0.9 / 10f64.powf(0.125)).abs() < 1e-14);
    }

    #[test]
    fn error_of_one_gives_the_safety_factor_at_steady_state() {
        // With facold = 1 and err = 1, fac = 1/0.9: h_new = 0.9 h.
        let mut c = PiController::new(5, 0.9, 0.04, 0.2, 10.0);
        c.ln_facold = 0.0;
        let (ok, h) = c.next(1.0, 1.0);
        assert!(ok);
        assert!((h - 0.9).abs() < 1e-12);
    }
}
