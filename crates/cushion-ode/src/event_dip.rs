//! A crossing and back inside one segment of a step: the event function has one strict sign at
//! both ends of the segment, but its extremum toward zero may lie beyond zero (a contact that
//! opens and closes again between two scan points). The extremum is searched by golden
//! section on the dense output; the search stops at the first point found beyond zero.

/// Golden-section steps at most: the bracket shrinks to 0.618^25 ~ 6e-6 of the segment. A
/// crossing and back narrower than that may be missed.
const MAX_STEPS: usize = 25;

/// A point of `(a, b)` where `g` is zero or on the other side from `ga` (and `gb`, of the same
/// sign), with `g` there; `None` if the search finds no such point. One evaluation at the
/// middle first, then one at the vertex of the parabola through the ends and the middle if it
/// turns toward zero inside the segment, then golden section if `g` there is nearer zero than
/// at both ends: a segment where `g` runs one way costs one evaluation.
pub fn crossing_in_dip(
    mut g: impl FnMut(f64) -> f64,
    a: f64,
    ga: f64,
    b: f64,
    gb: f64,
) -> Option<(f64, f64)> {
    // minimise s g, s the sign of the ends
    let s = ga.signum();
    let beyond = |v: f64| s * v <= 0.0;
    let mid = 0.5 * (a + b);
    let g_mid = g(mid);
    if beyond(g_mid) {
        return Some((mid, g_mid));
    }
    // The parabola through the ends and the middle: where it turns toward zero inside the
    // segment, `g` is looked at there; if it turns back nowhere inside, no search.
    let (u0, um, u1) = (s * ga, s * g_mid, s * gb);
    let curvature = u0 - 2.0 * um + u1;
    if !(curvature > 0.0) {
        return None;
    }
    let theta = 0.5 + 0.25 * (u0 - u1) / curvature;
    if !(theta > 0.0 && theta < 1.0) {
        return None;
    }
    let vertex = a + theta * (b - a);
    let g_vertex = g(vertex);
    if beyond(g_vertex) {
        return Some((vertex, g_vertex));
    }
    if !(s * g_vertex < u0.min(u1)) {
        return None;
    }
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (a, b);
    let mut x1 = hi - r * (hi - lo);
    let mut x2 = lo + r * (hi - lo);
    let (mut f1, mut f2) = (g(x1), g(x2));
    for _ in 0..MAX_STEPS {
        if beyond(f1) {
            return Some((x1, f1));
        }
        if beyond(f2) {
            return Some((x2, f2));
        }
        if s * f1 < s * f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - r * (hi - lo);
            f1 = g(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + r * (hi - lo);
            f2 = g(x2);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_brief_dip_below_zero_is_found() {
        // positive at both ends, below zero on (0.62, 0.66) only
        let g = |t: f64| (t - 0.64).powi(2) - 4e-4;
        let (t, v) = crossing_in_dip(g, 0.0, g(0.0), 1.0, g(1.0)).unwrap();
        assert!(v <= 0.0 && t > 0.62 && t < 0.66, "{t} {v}");
    }

    #[test]
    fn a_rise_above_zero_from_below_is_found() {
        let g = |t: f64| 1e-6 - (t - 0.2).powi(2);
        let (t, v) = crossing_in_dip(g, 0.0, g(0.0), 1.0, g(1.0)).unwrap();
        assert!(v >= 0.0 && (t - 0.2).abs() < 1e-3, "{t} {v}");
    }

    #[test]
    fn a_dip_that_stays_above_zero_gives_none() {
        let g = |t: f64| (t - 0.3).powi(2) + 1e-9;
        assert_eq!(crossing_in_dip(g, 0.0, g(0.0), 1.0, g(1.0)), None);
    }
}
