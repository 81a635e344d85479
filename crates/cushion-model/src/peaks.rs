//! Peaks inside steps: the step that holds the largest sample of a quantity (`|F_r|`, `F_c`,
//! the stroke) keeps its dense output, and the peak is located in it once, at the end of the
//! run, by Brent's search.
//!
//! The physics is sampled at every step's end, and at three points inside where a new peak is
//! possible (`observe/peak_sampler.rs`). (Where `F_r` jumps, at a step's start, that first
//! value is kept apart, `fr_after_jump`: a value at a jump needs no search.) When the
//! largest sample is a step's end, the peak may lie on either side of it: just before it in
//! that step, or just after it in the next one. The next step is then kept as well and both
//! sides are searched (`tests/peaks.rs::peaks_just_after_a_step_end_are_found`).
//!
//! Two peaks of nearly the same height in different places (a bistable module's back-stop
//! impact and a later one, 0.04 % apart) may be sampled in the wrong order: the one with the
//! larger sample need not hold the larger peak, least of all where the steps are long. The
//! steps with the largest samples of up to three other peaks within [`rival_window`] of the
//! best are kept as rivals and refined too (a peak is another one when the step ends have
//! fallen more than [`RIVAL`] below the previous one's largest sample since it). A step whose
//! largest sample is overtaken after the quantity fell by less than that (one peak with two
//! tops and a shallow dip) is kept as a rival as well: its top may be the higher one.

use crate::model::{Regime, MAX_STATES};
use crate::physics::Segment;

/// Samples of the physics per step (besides its start).
pub(crate) const K: usize = 4;

/// The most states the physics reads (tool 2 + liquid 2 + object 2; they come first in the
/// layout): the ledger's quadratures after them do not enter any force.
pub(crate) const MAX_DYNAMIC: usize = 6;

/// A step as five equally spaced nodes of its dense output (a polynomial of degree 4 in `t`,
/// so the nodes reproduce it exactly), with the robot segment and regime it ran in. Only the
/// states the physics reads are kept.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PeakStep {
    pub ts: [f64; K + 1],
    pub nodes: [[f64; MAX_DYNAMIC]; K + 1],
    pub seg: Segment,
    pub regime: Regime,
    /// Index of the largest sample.
    pub k: usize,
}

impl PeakStep {
    /// The state at `t` by Lagrange interpolation through the nodes (exact for the degree-4
    /// dense output of DOPRI5 and for the cubic Hermite of the fixed-step methods); the
    /// quadratures after the kept states are zero.
    pub fn state_at(&self, t: f64) -> [f64; MAX_STATES] {
        let mut y = [0.0; MAX_STATES];
        for j in 0..=K {
            let mut l = 1.0;
            for m in 0..=K {
                if m != j {
                    l *= (t - self.ts[m]) / (self.ts[j] - self.ts[m]);
                }
            }
            for (yi, ni) in y.iter_mut().zip(self.nodes[j].iter()) {
                *yi += l * ni;
            }
        }
        y
    }
}

/// By how much (relative) the step ends must fall below a peak's largest sample for a later
/// rise to be another peak.
pub(crate) const RIVAL: f64 = 1e-2;

/// Relative distance below the largest sample within which another peak is kept and refined as
/// well, at the tolerance `rtol`: `RIVAL (rtol / 1e-6)^0.4` within `[RIVAL, 0.2]`. A sample
/// lies below its peak by about the square of the step (a 5th-order method's step grows like
/// `rtol^(1/5)`), and at loose tolerances by more than `RIVAL`: there the peak whose sample
/// happens to lie lowest may be the largest
/// (`tests::a_peak_sampled_low_among_several_near_ones_is_still_found`). At rtol 1e-6 and
/// tighter the window is `RIVAL`, which keeps the extra refinements rare.
pub(crate) fn rival_window(rtol: f64) -> f64 {
    (RIVAL * (rtol / 1e-6).powf(0.4)).clamp(RIVAL, 0.2)
}

/// `v` lowered by the fraction `by` of its size: the edge of a window (or a dip) below a sample.
#[inline(always)]
fn below(v: f64, by: f64) -> f64 {
    v - by * v.abs()
}

/// Other peaks kept besides the best (the largest samples among those in the window).
const RIVALS: usize = 3;

/// Two refined peaks within this relative distance are the same height (to rounding: the
/// search finds a smooth peak to ~1e-14), and the earlier one is the peak. A bistable spring's
/// two extreme forces are equal and opposite, so a tool that crosses both slowly meets the
/// same largest `|F_r|` twice; without a rule, rounding would choose the sign and the time
/// (`tests::of_two_peaks_of_the_same_height_the_earlier_is_the_peak`).
pub(crate) const TIE: f64 = 1e-12;

/// Another peak's step (and the one after it, if kept) with its largest sample.
type Rival = (PeakStep, Option<PeakStep>, f64);

/// Where one quantity's peak is: the step with its largest sample and, when that sample is the
/// step's end, the step after it; and the steps with the largest samples of up to [`RIVALS`]
/// other peaks within [`rival_window`] of it.
#[derive(Clone, Debug, Default)]
pub(crate) struct PeakCandidate {
    pub at: Option<PeakStep>,
    pub after: Option<PeakStep>,
    wants_next: bool,
    /// The largest sample (the one `at` holds), or the value at the start.
    best: f64,
    /// [`rival_window`] at the run's tolerance.
    window: f64,
    /// A step has ended more than `RIVAL` below `best` since `at`.
    dipped: bool,
    /// A step has ended below `best` since `at` (the quantity turned there, by any amount).
    fell: bool,
    /// At most [`RIVALS`]; on the heap, allocated only when a rival comes up, so that the
    /// model, moved whole a few times per run, stays small.
    rivals: Vec<Option<Rival>>,
    /// The slot of the rival whose peak is still rising or at its top (no step has ended more
    /// than `RIVAL` below it since): a larger sample of that peak replaces it there.
    rising: Option<usize>,
}

impl PeakCandidate {
    /// No step kept yet; `best` is the value at the start, which a peak must exceed; rivals
    /// within `window` (relative, [`rival_window`]) are kept.
    pub fn starting_at(best: f64, window: f64) -> PeakCandidate {
        PeakCandidate {
            best,
            window,
            ..PeakCandidate::default()
        }
    }

    /// The slot for a rival whose largest sample is `value`: a free one, a new one while fewer
    /// than [`RIVALS`] are kept, or the smallest rival's if `value` is larger; `None` if every
    /// rival kept is at least as large.
    fn slot_for(&mut self, value: f64) -> Option<usize> {
        if let Some(free) = self.rivals.iter().position(Option::is_none) {
            return Some(free);
        }
        if self.rivals.len() < RIVALS {
            self.rivals.push(None);
            return Some(self.rivals.len() - 1);
        }
        let (i, smallest) = self
            .rivals
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().map(|r| (i, r.2)))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        (smallest < value).then_some(i)
    }

    /// A new largest sample `value`, in `step` at node `step.k`. The step that held the
    /// previous one becomes a rival if the quantity fell after it (another peak, or another top
    /// of this one), near enough.
    // runs on every new largest sample: as a call, moving the step in and out, it costs about
    // 1 % of a run's instructions (`bash bench/instructions.sh`)
    #[inline(always)]
    fn set(&mut self, step: PeakStep, value: f64) {
        if let Some(i) = self.rising.take() {
            // the rising rival's peak is this one: `at` takes it over
            self.rivals[i] = None;
        }
        let window = below(value, self.window);
        // the old step is kept if its quantity turned after it (`fell`; a dip of `RIVAL` is a
        // fall too), even by less than `RIVAL`: then the two are one peak with two tops and a
        // shallow dip, and the larger sample need not hold the larger top (a long step's
        // samples can miss the first top; `tests::a_higher_top_before_a_shallow_dip_is_found`);
        // while it rises, never
        if self.fell && self.best >= window {
            if let Some(old) = self.at.take() {
                if let Some(i) = self.slot_for(self.best) {
                    self.rivals[i] = Some((old, self.after.take(), self.best));
                }
            }
        }
        for r in self.rivals.iter_mut() {
            if r.as_ref().is_some_and(|r| r.2 < window) {
                *r = None;
            }
        }
        self.wants_next = step.k == K;
        self.at = Some(step);
        self.after = None;
        self.best = value;
        self.dipped = false;
        self.fell = false;
    }

    /// A step whose largest sample `value` is not a new largest one: kept as a rival if it
    /// belongs to another peak and comes near the best (`step` builds it).
    fn offer(&mut self, value: f64, step: impl FnOnce() -> PeakStep) {
        if !(self.at.is_some() && self.dipped && value >= below(self.best, self.window)) {
            return;
        }
        match self.rising {
            // the same peak as the rival still rising: keep its larger sample
            Some(i) => {
                if self.rivals[i].as_ref().is_none_or(|r| r.2 < value) {
                    self.rivals[i] = Some((step(), None, value));
                }
            }
            None => {
                if let Some(i) = self.slot_for(value) {
                    self.rivals[i] = Some((step(), None, value));
                    self.rising = Some(i);
                }
            }
        }
    }

    /// One step: its largest sample `value`, in the step that `step` builds, and the sample
    /// `end` at its end. Returns whether `value` is a new largest sample.
    pub fn observe(&mut self, value: f64, end: f64, step: impl FnOnce() -> PeakStep) -> bool {
        let is_new = value > self.best;
        if is_new {
            self.set(step(), value);
        } else {
            self.offer(value, step);
        }
        self.note_end(end);
        is_new
    }

    /// The sample at a step's end (after `set` or `offer` for that step).
    fn note_end(&mut self, value: f64) {
        if value < self.best {
            self.fell = true;
        }
        if value < below(self.best, RIVAL) {
            self.dipped = true;
        }
        if let Some(i) = self.rising {
            let top = self.rivals[i].as_ref().map_or(f64::INFINITY, |r| r.2);
            if value < below(top, RIVAL) {
                self.rising = None;
            }
        }
    }

    /// Whether the step that follows should be kept (see [`Self::follow`]).
    pub fn wants_next(&self) -> bool {
        self.wants_next
    }

    /// The step right after the one holding the largest sample at its end.
    pub fn follow(&mut self, next: PeakStep) {
        if self.wants_next {
            self.after = Some(next);
            self.wants_next = false;
        }
    }

    /// The largest value of `f(step, t)` near the largest sample, whose value is `f_best`:
    /// within the two sample intervals around it, and in the first sample interval of the next
    /// step when the sample is a step's end; of the best and the rival peaks the largest, or the
    /// earliest of those the same height ([`TIE`]). Returns `(t, value, the step that holds
    /// it)`; `None` without a candidate.
    pub fn locate(
        &self,
        f: impl Fn(&PeakStep, f64) -> f64,
        f_best: f64,
    ) -> Option<(f64, f64, &PeakStep)> {
        let c = self.at.as_ref()?;
        let mut best = locate_in(c, self.after.as_ref(), &f, f_best);
        for (r, after, value) in self.rivals.iter().flatten() {
            let other = locate_in(r, after.as_ref(), &f, *value);
            let tie = (other.1 - best.1).abs() <= TIE * other.1.abs().max(best.1.abs());
            if (tie && other.0 < best.0) || (!tie && other.1 > best.1) {
                best = other;
            }
        }
        Some(best)
    }
}

/// The largest value of `f` around the sample `f_best` at node `c.k` of step `c`, and in the
/// first sample interval of the step `after` it.
fn locate_in<'a>(
    c: &'a PeakStep,
    after: Option<&'a PeakStep>,
    f: &impl Fn(&PeakStep, f64) -> f64,
    f_best: f64,
) -> (f64, f64, &'a PeakStep) {
    let (lo, hi) = (c.ts[c.k.saturating_sub(1)], c.ts[(c.k + 1).min(K)]);
    let (t, v) = brent_max(|t| f(c, t), lo, hi, (c.ts[c.k], f_best));
    let mut best = (t, v, c);
    if let Some(n) = after {
        // from the shared end point, a bracket end here
        let (t, v) = brent_max(|t| f(n, t), n.ts[0], n.ts[1], (n.ts[0], f(n, n.ts[0])));
        if v > best.1 {
            best = (t, v, n);
        }
    }
    best
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
