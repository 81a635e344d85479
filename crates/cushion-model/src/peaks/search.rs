//! A top searched on the dense output: Brent's method for the largest value in the bracket
//! the samples gave (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973,
//! ch. 5), on either side of a step's start where the bracket straddles it, and the point
//! found evaluated on the side it was found on (a quantity may jump there).

use super::tracker::{Bracket, Peak};
use crate::model::Eval;

/// Which side of a step's start a located point lies on: a quantity may jump there (`F_r`
/// where the robot's acceleration jumps under a rigid tool), so a point at the start itself
/// must be evaluated on the side it was found on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Side {
    Before,
    After,
}

/// Search the top `b` whose bracket may straddle `split` (a step's start): on `before` left of
/// it and on `after` right of it, each side from its own known point. Returns the largest
/// point, `(t, value)`, and the side it was found on.
pub(crate) fn search(
    b: Bracket,
    split: f64,
    before: impl Fn(f64) -> f64,
    after: impl Fn(f64) -> f64,
) -> (f64, f64, Side) {
    if b.lo >= split {
        let (t, v) = brent_max(after, b.lo, b.hi, (b.t, b.v));
        return (t, v, Side::After);
    }
    // the top is the shared point, or left of it (at the run's end)
    let left = brent_max(before, b.lo, b.t, (b.t, b.v));
    if b.hi <= split {
        return (left.0, left.1, Side::Before);
    }
    let right = brent_max(&after, split, b.hi, (split, after(split)));
    if right.1 > left.1 {
        (right.0, right.1, Side::After)
    } else {
        (left.0, left.1, Side::Before)
    }
}

/// The top of `value` in the bracket `b`, searched on `behind` before `split` and on `here`
/// from it ([`search`]), with what is reported for it where it was found.
#[inline(always)]
pub(crate) fn locate_on(
    b: Bracket,
    split: f64,
    value: impl Fn(&Eval) -> (f64, f64),
    here: impl Fn(f64) -> Eval,
    behind: impl Fn(f64) -> Eval,
) -> Peak {
    let (t, v, side) = search(b, split, |t| value(&behind(t)).0, |t| value(&here(t)).0);
    let e = match side {
        Side::Before => behind(t),
        Side::After => here(t),
    };
    Peak {
        t,
        value: v,
        reported: value(&e).1,
    }
}

/// Largest value of `f` on `[lo, hi]` by Brent's method (golden-section steps, parabolic
/// steps where the parabola through the three best points is trusted), starting from a known
/// point `(t, f(t))` in the bracket. Returns the best point seen; the bracket shrinks to 1e-7
/// of its width, so a smooth peak's value is right to ~1e-14 relative.
pub(crate) fn brent_max(f: impl Fn(f64) -> f64, lo: f64, hi: f64, start: (f64, f64)) -> (f64, f64) {
    const GOLD: f64 = 0.381_966_011_250_105_1; // (3 - sqrt 5) / 2
    let (mut a, mut b) = (lo.min(hi), lo.max(hi));
    let tol = 1e-7 * (b - a) + 1e-300;
    // minimise g = -f; x best, w second best, v the previous w
    let (mut x, mut fx) = (start.0.clamp(a, b), -start.1);
    let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if (x - m).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut parabolic = false;
        if e.abs() > tol {
            let r = (x - w) * (fx - fv);
            let q0 = (x - v) * (fx - fw);
            let mut p = (x - v) * q0 - (x - w) * r;
            let mut q = 2.0 * (q0 - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let e_before = e;
            e = d;
            if p.abs() < (0.5 * q * e_before).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = tol.copysign(m - x);
                }
                parabolic = true;
            }
        }
        if !parabolic {
            e = if x >= m { a - x } else { b - x };
            d = GOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = -f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, -fx)
}
