//! Peaks found as the samples come: each quantity (`|F_r|`, `F_c`, the stroke) is sampled at
//! every step's end and at three points inside where a new peak is possible
//! (`observe/peak_sampler.rs`), and every local top of its samples that comes near the largest
//! value so far is located at once, by Brent's search on the dense output around it: the
//! two sample intervals on either side of the top sample.
//!
//! That is one rule for every case. A top inside a step is searched on that step's own dense
//! output, exact for any method. A top at a step's end is confirmed only by the next step's
//! first sample, and the peak may lie on either side of it: the step before is then kept (its
//! dense output, [`KeptStep`]) and both sides are searched
//! (`tests/peaks.rs::peaks_just_after_a_step_end_are_found`). Several tops of nearly the same
//! height (a bistable module's back-stop impact and a later one, 0.04 % apart; one peak with
//! two tops and a shallow dip) are each searched, so the one with the larger sample need not
//! hold the larger peak. Where a quantity jumps (`F_r` at a robot kink under a rigid tool) the
//! value after the jump is exact where it is, and is offered as found ([`PeakTracker::found`]).

use crate::model::{Eval, Model, Regime, MAX_STATES};
use crate::physics::Segment;
use cushion_ode::{DenseOutput, State};

/// Samples of the physics per step (besides its start).
pub(crate) const K: usize = 4;

/// The most states the physics reads (tool 2 + liquid 2 + object 2; they come first in the
/// layout): the ledger's quadratures after them do not enter any force.
pub(crate) const MAX_DYNAMIC: usize = 6;

/// A step kept while the sample at its end may be a top: its dense output (the states the
/// physics reads, [`DenseOutput::leading`]), with the robot segment and regime it ran in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KeptStep {
    pub dense: DenseOutput<MAX_DYNAMIC>,
    pub seg: Segment,
    pub regime: Regime,
    /// Whether its dense output is stable (`cushion_ode::Step::dense_stable`).
    pub dense_stable: bool,
}

impl KeptStep {
    /// The states the physics reads at the step's start.
    pub fn start(&self) -> State<MAX_DYNAMIC> {
        self.dense.eval(self.dense.t0)
    }

    /// The physics at `t` on the step's dense output, in the segment and regime the step ran
    /// in (the quadratures after the kept states, which no force reads, are zero).
    pub fn eval(&self, model: &Model, t: f64) -> Eval {
        let mut y = [0.0; MAX_STATES];
        y[..MAX_DYNAMIC].copy_from_slice(self.dense.eval(t).as_slice());
        let n = model.layout.n.clamp(1, MAX_STATES);
        model.eval(t, &y[..n], &self.seg, &self.regime)
    }
}

/// A sample's relative distance below its top, which sets how near the largest value so far a
/// top must come to be searched: at the tolerance `rtol`, `0.01 (rtol / 1e-6)^0.4` within
/// `[0.01, 0.2]`. A sample lies below its peak by about the square of the step (a 5th-order
/// method's step grows like `rtol^(1/5)`), and at loose tolerances by more than 1 %: there the
/// peak whose sample happens to lie lowest may be the largest
/// (`tests::a_peak_sampled_low_among_several_near_ones_is_still_found`). At rtol 1e-6 and
/// tighter the window is 1 %, which keeps the searches rare.
pub(crate) fn top_window(rtol: f64) -> f64 {
    const NARROWEST: f64 = 1e-2;
    (NARROWEST * (rtol / 1e-6).powf(0.4)).clamp(NARROWEST, 0.2)
}

/// Two located values within this relative distance are the same height (to rounding: the
/// search finds a smooth peak to ~1e-14), and the earlier one is the peak. A bistable spring's
/// two extreme forces are equal and opposite, so a tool that crosses both slowly meets the
/// same largest `|F_r|` twice; without a rule, rounding would choose the sign and the time
/// (`tests::of_two_peaks_of_the_same_height_the_earlier_is_the_peak`).
pub(crate) const TIE: f64 = 1e-12;

/// A top to search: the sample `(t, v)`, which rose from the sample at `lo` and fell to the
/// one at `hi` (at the run's end, `hi = t`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bracket {
    pub lo: f64,
    pub t: f64,
    pub v: f64,
    pub hi: f64,
}

/// A located value: its time, its value, and what the caller reports for it (the signed force
/// where the value is `|F_r|`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Peak {
    pub t: f64,
    pub value: f64,
    pub reported: f64,
}

/// One quantity's peak, found as its samples arrive.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PeakTracker {
    /// The largest value located so far (the value at the start until a top beats it).
    pub peak: Peak,
    /// The largest value seen, sample or located: a top is searched if its sample comes
    /// within `window` of it.
    known: f64,
    window: f64,
    /// The last sample, the time of the one before it, and whether it rose from that one.
    last: (f64, f64),
    before: f64,
    rising: bool,
}

impl PeakTracker {
    /// The value at the start, `start` (exact: a peak must exceed it); tops within `window`
    /// (relative, [`top_window`]) of the largest value are searched.
    pub fn starting_at(start: Peak, window: f64) -> PeakTracker {
        PeakTracker {
            peak: start,
            known: start.value,
            window,
            last: (start.t, start.value),
            before: start.t,
            rising: false,
        }
    }

    /// Whether a sample `v` is near enough the largest value seen for its top to be searched.
    #[inline(always)]
    fn near(&self, v: f64) -> bool {
        v >= self.known - self.window * self.known.abs()
    }

    /// The next sample, `v` at `t`. Returns the top it confirms (the last sample, if it rose
    /// to there and `v` is not above it) when that comes near the largest value seen.
    #[inline]
    pub fn sample(&mut self, t: f64, v: f64) -> Option<Bracket> {
        let (t_last, v_last) = self.last;
        // a sample equal to the last confirms it as well: two samples either side of a top,
        // equally far from it, are the same value and hold it between them
        // (`tests::a_peak_sampled_low_among_several_near_ones_is_still_found`), and a quantity
        // that overshoots into a plateau (a contact force as the object sticks) has its top
        // just before the plateau's first sample
        // (`tests::a_top_before_a_plateau_is_found`)
        let top = (self.rising && v <= v_last && self.near(v_last)).then_some(Bracket {
            lo: self.before,
            t: t_last,
            v: v_last,
            hi: t,
        });
        self.known = self.known.max(v);
        self.rising = v > v_last;
        self.before = t_last;
        self.last = (t, v);
        top
    }

    /// The largest value seen, sample or located.
    #[inline]
    pub fn largest(&self) -> f64 {
        self.known
    }

    /// Whether the last sample may still prove a top to search (it rose, near the largest
    /// value seen): the step it ends must be kept until the next sample comes.
    #[inline]
    pub fn may_top(&self) -> bool {
        self.rising && self.near(self.last.1)
    }

    /// At the run's end: the last sample as a top, if it may be one (it rose to the end).
    pub fn open_top(&self) -> Option<Bracket> {
        self.may_top().then_some(Bracket {
            lo: self.before,
            t: self.last.0,
            v: self.last.1,
            hi: self.last.0,
        })
    }

    /// A located value: a searched top, or an exact value (where the quantity jumps). It is
    /// the peak if it is larger, or the same height ([`TIE`]) and earlier.
    pub fn found(&mut self, p: Peak) {
        let best = self.peak.value;
        let tie = (p.value - best).abs() <= TIE * p.value.abs().max(best.abs());
        if (tie && p.t < self.peak.t) || (!tie && p.value > best) {
            self.peak = p;
        }
        self.known = self.known.max(p.value);
    }
}

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

#[cfg(test)]
mod tests;
