//! Event location: a bracketing root finder (Illinois regula falsi, safeguarded by bisection)
//! on the dense output. Detection lives in `solve.rs`: signs are compared at the step's ends and
//! at interior points of the dense output, so two crossings inside one step are both found.

/// Find the crossing of `g` inside `[a, b]`, where `ga` is strictly on the old side and `gb` on
/// the new side (or zero). Returns the time on the far side of the crossing: a point where `g`
/// is on the new side (or zero), within a few ulp of the exact root, so the event cannot fire
/// again from there.
pub fn locate(
    mut g: impl FnMut(f64) -> f64,
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
) -> f64 {
    debug_assert!(ga != 0.0);
    let old_negative = ga < 0.0;
    let on_new_side = |x: f64| if old_negative { x >= 0.0 } else { x <= 0.0 };
    if gb == 0.0 {
        // Still search: the first zero may be earlier than b; the bracket logic handles it.
    }
    // Weighted values for the Illinois modification.
    let (mut wa, mut wb) = (ga, gb);
    let mut last_kept: i8 = 0; // +1: b moved last, -1: a moved last
    let mut width_before = b - a;
    for iter in 0..200 {
        let scale = a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
        if b - a <= 4.0 * f64::EPSILON * scale {
            break;
        }
        let mut m = if wb != wa {
            b - wb * (b - a) / (wb - wa)
        } else {
            0.5 * (a + b)
        };
        // Safeguard: every third iteration must have halved the bracket, else bisect.
        if iter % 3 == 2 {
            if b - a > 0.5 * width_before {
                m = 0.5 * (a + b);
            }
            width_before = b - a;
        }
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
            if !(m > a && m < b) {
                break; // a and b are adjacent floats
            }
        }
        let gm = g(m);
        if on_new_side(gm) {
            b = m;
            gb = gm;
            wb = gm;
            if last_kept == 1 {
                wa *= 0.5;
            }
            last_kept = 1;
        } else {
            a = m;
            ga = gm;
            wa = gm;
            if last_kept == -1 {
                wb *= 0.5;
            }
            last_kept = -1;
        }
    }
    let _ = (ga, gb);
    b
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
