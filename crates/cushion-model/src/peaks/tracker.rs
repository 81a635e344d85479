//! One quantity's peak, found as its samples arrive: the tracker keeps the largest value seen
//! and confirms a top (a sample that rose and is not exceeded by the next) when it comes near
//! that value, and it keeps the located peak, the earlier of two of the same height.
//!
//! How near is near ([`top_window`]) follows from how far below its top a sample may lie, at
//! the tolerance: the step of a 5th-order method grows like `rtol^(1/5)` and a sample lies
//! below the peak by about its square.

/// A sample's relative distance below its top, which sets how near the largest value so far a
/// top must come to be searched: at the tolerance `rtol`, `0.01 (rtol / 1e-6)^0.4` within
/// `[0.01, 0.2]`. A sample lies below its peak by about the square of the step (a 5th-order
/// method's step grows like `rtol^(1/5)`), and at loose tolerances by more than 1 %: there the
/// peak whose sample happens to lie lowest may be the largest
/// (`peaks/tests.rs::a_peak_sampled_low_among_several_near_ones_is_still_found`). At rtol 1e-6 and
/// tighter the window is 1 %, which keeps the searches rare.
pub(crate) fn top_window(rtol: f64) -> f64 {
    const NARROWEST: f64 = 1e-2;
    (NARROWEST * (rtol / 1e-6).powf(0.4)).clamp(NARROWEST, 0.2)
}

/// Two located values within this relative distance are the same height (to rounding: the
/// search finds a smooth peak to ~1e-14), and the earlier one is the peak. A bistable spring's
/// two extreme forces are equal and opposite, so a tool that crosses both slowly meets the
/// same largest `|F_r|` twice; without a rule, rounding would choose the sign and the time
/// (`peaks/tests.rs::of_two_peaks_of_the_same_height_the_earlier_is_the_peak`).
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
        // (`peaks/tests.rs::a_peak_sampled_low_among_several_near_ones_is_still_found`), and a quantity
        // that overshoots into a plateau (a contact force as the object sticks) has its top
        // just before the plateau's first sample
        // (`peaks/tests.rs::a_top_before_a_plateau_is_found`)
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
