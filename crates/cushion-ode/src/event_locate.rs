//! Where an event function crosses zero between two points of a step's dense output: a
//! bracketing root finder that ends on the far side of the crossing, so that the event
//! cannot fire again from there.

/// Find the crossing of `g` inside `[a, b]`, where `ga` is strictly on the old side and `gb` on
/// the new side (or zero). Returns the time on the far side of the crossing: a point where `g`
/// is on the new side (or zero), within a few ulp of the exact root, so the event cannot fire
/// again from there.
///
/// Regula falsi with Anderson and Björck's weights (the end kept twice in a row has its value
/// scaled by `1 - g_new / g_old`, or halved where that is not positive: superlinear, order
/// about 1.7, where Illinois's halving has 1.44), and, as in Brent's zeroin, no point closer
/// than `tol` to an end of the bracket: once the iterates have converged on one side, the
/// next one lands `tol` past them and closes the bracket, instead of creeping up on the root
/// from that side while the far end stays where it was. Every third iteration must have
/// halved the bracket, else it bisects (a flat crossing, `tests::flat_function_converges_by_bisection`).
pub fn locate(mut g: impl FnMut(f64) -> f64, mut a: f64, mut ga: f64, mut b: f64, gb: f64) -> f64 {
    debug_assert!(ga != 0.0);
    let old_negative = ga < 0.0;
    let on_new_side = |x: f64| if old_negative { x >= 0.0 } else { x <= 0.0 };
    // the values the secant uses (scaled by the weights), and which end moved last
    let (mut wa, mut wb) = (ga, gb);
    let mut last_kept: i8 = 0; // +1: b moved last, -1: a moved last
    let mut width_before = b - a;
    // the old side's point before `a` (none yet: at `a`'s left), for the extrapolation below
    let mut prev = (f64::NEG_INFINITY, f64::NAN);
    for iter in 0..200 {
        let scale = a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
        let tol = 2.0 * f64::EPSILON * scale;
        if b - a <= 2.0 * tol {
            break;
        }
        let mut m = if wb == 0.0 && prev.0 < a {
            // a zero on the new side gives the secant no slope (a force that is exactly zero
            // once a contact has let go): extrapolate the old side's last two points instead
            let (tp, gp) = prev;
            a - ga * (a - tp) / (ga - gp)
        } else if wb != wa {
            b - wb * (b - a) / (wb - wa)
        } else {
            0.5 * (a + b)
        };
        if iter % 3 == 2 {
            if b - a > 0.5 * width_before {
                m = 0.5 * (a + b);
            }
            width_before = b - a;
        }
        if !(m >= a && m <= b) {
            m = 0.5 * (a + b);
        }
        // at least `tol` inside either end (the bracket is wider than 2 tol here): a secant
        // point that rounds to an end, the root within rounding of it, probes `tol` inside
        m = m.clamp(a + tol, b - tol);
        if !(m > a && m < b) {
            break; // a and b are adjacent floats
        }
        let gm = g(m);
        if on_new_side(gm) {
            if last_kept == 1 {
                wa *= anderson_bjorck(gm, wb);
            }
            b = m;
            wb = gm;
            last_kept = 1;
        } else {
            if last_kept == -1 {
                wb *= anderson_bjorck(gm, wa);
            }
            prev = (a, ga);
            a = m;
            ga = gm;
            wa = gm;
            last_kept = -1;
        }
    }
    b
}

/// Anderson and Björck's factor for the value at the end kept again, when the new point `g_new`
/// replaced the other end's (weighted) value `g_old` on the same side: `1 - g_new / g_old`, or
/// `1/2` where that is not positive (the new point is no nearer zero).
fn anderson_bjorck(g_new: f64, g_old: f64) -> f64 {
    let m = 1.0 - g_new / g_old;
    if m > 0.0 {
        m
    } else {
        0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_simple_root_to_a_few_ulp_on_the_far_side() {
        let root = 2f64.sqrt();
        let t = locate(|x| x * x - 2.0, 1.0, -1.0, 2.0, 2.0);
        assert!(t * t - 2.0 >= 0.0, "far side");
        assert!(
            (t - root).abs() <= 4.0 * f64::EPSILON * 2.0,
            "{t} vs {root}"
        );
    }

    #[test]
    fn falling_crossing_far_side_is_on_the_new_side() {
        let t = locate(|x| (x).cos(), 1.0, 1f64.cos(), 2.0, 2f64.cos());
        assert!(t.cos() <= 0.0);
        assert!((t - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    /// `locate` with the evaluations of `g` counted.
    fn counted(g: impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, usize) {
        let n = std::cell::Cell::new(0);
        let t = locate(
            |x| {
                n.set(n.get() + 1);
                g(x)
            },
            a,
            g(a),
            b,
            g(b),
        );
        (t, n.get())
    }

    #[test]
    fn a_smooth_root_takes_few_evaluations() {
        // a contact's gap closing and turning: 1e-3 - t + 40 t^2 on a 3 ms step
        let g = |t: f64| 1e-3 - t + 40.0 * t * t;
        let root = (1.0 - (1.0f64 - 0.16).sqrt()) / 80.0;
        let (t, n) = counted(g, 0.0, 3e-3);
        assert!(
            g(t) <= 0.0 && (t - root).abs() <= 4.0 * f64::EPSILON * t,
            "{t} vs {root}"
        );
        assert!(n <= 8, "{n} evaluations");
    }

    #[test]
    fn a_root_within_rounding_of_the_far_end_closes_at_once() {
        // the first secant point lands on the root to rounding (the scene's first contact, a
        // gap closing at constant speed); the next probes just inside it
        let g = |t: f64| 1e-3 - t;
        let (t, n) = counted(g, 0.8e-3, 1.06e-3);
        assert!(
            g(t) <= 0.0 && (t - 1e-3).abs() <= 4.0 * f64::EPSILON * 1e-3,
            "{t}"
        );
        assert!(n <= 4, "{n} evaluations");
    }

    #[test]
    fn a_value_that_stays_exactly_zero_past_the_root_is_extrapolated() {
        // a contact force that is zero once the contact has let go (at 2e-3): no slope on the
        // new side, where regula falsi would only bisect
        let g = |t: f64| (2e-3 - t).max(0.0) * 5.0;
        let (t, n) = counted(g, 1e-3, 4e-3);
        assert!(
            g(t) <= 0.0 && (t - 2e-3).abs() <= 4.0 * f64::EPSILON * 2e-3,
            "{t}"
        );
        assert!(n <= 8, "{n} evaluations");
    }

    #[test]
    fn flat_function_converges_by_bisection() {
        // x^9 is very flat near 0: regula falsi alone stalls.
        let t = locate(
            |x: f64| (x - 0.3).powi(9),
            0.0,
            -(0.3f64.powi(9)),
            1.0,
            0.7f64.powi(9),
        );
        assert!((t - 0.3).abs() < 1e-3, "{t}");
        assert!((t - 0.3f64).powi(9) >= 0.0);
    }
}
