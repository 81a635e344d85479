//! Where an event function that is closing on zero will cross it, forecast from the step just
//! taken, so that the next step can end there instead of running past it.
//!
//! An event usually marks a change of regime in `f` (a contact that begins, a stop that is
//! reached). A step that runs from the smooth side deep into the new regime has an error
//! estimate far above the tolerance, or stages that overflow, and is rejected, often several
//! times, each rejection shrinking the step by the controller's largest factor. A step that
//! ends where the function crosses zero is accepted as a smooth step; the event is then found
//! at or just past its end. Esposito, Kumar and Pappas ("Accurate event detection for
//! simulating hybrid systems", HSCC 2001) adapt the step near an event surface in the same
//! spirit.
//!
//! The forecast is the quadratic in time through the function's values at the step's start,
//! middle (on the dense output) and end, extrapolated past the end: its first zero. A function
//! that turns back before zero (a grazing approach) has no real zero and gives no forecast.

/// How far past a step's end a crossing is forecast, in steps of its length: the controller
/// grows a step by at most this factor (DOPRI5's largest ratio).
pub(crate) const FORECAST_REACH: f64 = 10.0;

/// Whether a function with the values `a` and `b` at a step's start and end, strictly on one
/// side of zero, closes on it with a chord that reaches zero within [`FORECAST_REACH`] steps
/// past the end: the functions worth a forecast (the events' and the kinks').
pub(crate) fn closes_within_reach(a: f64, b: f64) -> bool {
    let same_side = (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0);
    // b / (a - b): the chord's zero past the end, in steps of its length
    same_side && b.abs() < a.abs() && b / (a - b) <= FORECAST_REACH
}

/// The first time `tau > 0` after the step's end at which the quadratic through
/// `(-span, g0)`, `(-span / 2, g_mid)` and `(0, g1)` is zero, if it has such a zero.
/// `g1` must be nonzero.
pub fn zero_after(span: f64, g0: f64, g_mid: f64, g1: f64) -> Option<f64> {
    // g(tau) = g1 + b tau + c tau^2: from g(-span) = g0 and g(-span/2) = g_mid,
    // c span^2 / 2 = (g0 - g1) - 2 (g_mid - g1) and b span = c span^2 - (g0 - g1).
    let (d0, dm) = (g0 - g1, g_mid - g1);
    let c = 2.0 * (d0 - 2.0 * dm) / (span * span);
    let b = (c * span * span - d0) / span;
    let disc = b * b - 4.0 * c * g1;
    if !(disc >= 0.0) {
        return None;
    }
    // The two roots without cancellation: q / c and g1 / q (Numerical Recipes, 5.6).
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let roots = [q / c, g1 / q];
    roots
        .into_iter()
        .filter(|r| r.is_finite() && *r > 0.0)
        .min_by(f64::total_cmp)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of `g(t)` at `-span`, `-span / 2` and 0.
    fn samples(g: impl Fn(f64) -> f64, span: f64) -> (f64, f64, f64) {
        (g(-span), g(-0.5 * span), g(0.0))
    }

    #[test]
    fn a_quadratic_approach_is_forecast_exactly() {
        // g = 1 - 3 t - 2 t^2 falls through zero at t = (-3 + sqrt(17)) / 4 = 0.2807764...
        let g = |t: f64| 1.0 - 3.0 * t - 2.0 * t * t;
        let (g0, gm, g1) = samples(g, 0.1);
        let tau = zero_after(0.1, g0, gm, g1).unwrap();
        let exact = (-3.0 + 17f64.sqrt()) / 4.0;
        assert!((tau - exact).abs() < 1e-15, "{tau} vs {exact}");
    }

    #[test]
    fn a_straight_approach_is_forecast_exactly() {
        // c = 0: the root g1 / q of the stable form still holds
        let (g0, gm, g1) = samples(|t| 0.5 - 2.0 * t, 0.2);
        let tau = zero_after(0.2, g0, gm, g1).unwrap();
        assert!((tau - 0.25).abs() < 1e-15, "{tau}");
    }

    #[test]
    fn a_function_turning_back_before_zero_gives_none() {
        // g = 1 + (t - 0.1)^2 falls, then turns back at t = 0.1 without reaching zero
        let (g0, gm, g1) = samples(|t: f64| 1.0 + (t - 0.1).powi(2), 0.2);
        assert_eq!(zero_after(0.2, g0, gm, g1), None);
    }

    #[test]
    fn a_function_moving_away_gives_none() {
        let (g0, gm, g1) = samples(|t: f64| 1.0 + t, 0.2);
        assert_eq!(zero_after(0.2, g0, gm, g1), None);
    }

    #[test]
    fn a_smooth_approach_is_forecast_to_third_order() {
        // g = cos(t) - 0.5 crosses at pi/3, two steps past the step's end: the forecast's
        // error shrinks like span^3 (the quadratic's remainder), 0.0021 at span 0.1
        let err = |span: f64| {
            let t1 = std::f64::consts::FRAC_PI_3 - 2.0 * span;
            let (g0, gm, g1) = samples(|t| (t1 + t).cos() - 0.5, span);
            (zero_after(span, g0, gm, g1).unwrap() - 2.0 * span).abs()
        };
        let (e1, e2, e3) = (err(0.1), err(0.05), err(0.025));
        assert!(e1 < 0.03 * 0.1, "{e1}");
        assert!(e1 / e2 > 6.5 && e2 / e3 > 6.5, "{e1} {e2} {e3}");
    }
}
