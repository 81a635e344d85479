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
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn brent_finds_a_smooth_peak_to_round_off_in_few_evaluations() {
        // f = cos(t - 0.3) peaks at 0.3 with value 1; start from a sample at 0.25
        let calls = Cell::new(0);
        let f = |t: f64| {
            calls.set(calls.get() + 1);
            (t - 0.3).cos()
        };
        let (t, v) = brent_max(f, 0.2, 0.45, (0.25, (0.25f64 - 0.3).cos()));
        assert!((t - 0.3).abs() < 1e-7, "{t}");
        assert!((v - 1.0).abs() < 1e-14, "{v}");
        assert!(calls.get() <= 20, "{} evaluations", calls.get());
    }

    #[test]
    fn brent_returns_the_bracket_end_for_a_monotone_function() {
        let (t, v) = brent_max(|t| t * t, 1.0, 2.0, (1.5, 2.25));
        assert!((t - 2.0).abs() < 1e-6, "{t}");
        assert!((v - 4.0).abs() < 1e-5, "{v}");
    }

    #[test]
    fn brent_keeps_the_start_when_nothing_is_larger() {
        // a kink peak at the start point itself
        let (t, v) = brent_max(|t: f64| 1.0 - (t - 0.5).abs(), 0.0, 1.0, (0.5, 1.0));
        assert_eq!((t, v), (0.5, 1.0));
    }

    #[test]
    fn lagrange_nodes_reproduce_a_quartic() {
        let q = |t: f64| 1.0 + t - 2.0 * t * t + 0.5 * t.powi(3) - 0.25 * t.powi(4);
        let (step, _, _) = step_of(&q, 0.1, 0.2);
        for t in [0.1, 0.13, 0.2, 0.29] {
            assert!((step.state_at(t)[0] - q(t)).abs() < 1e-14);
        }
    }

    /// A step of `f` over `[t0, t0 + h]`: its five nodes, its largest sample marked.
    fn step_of(f: &impl Fn(f64) -> f64, t0: f64, h: f64) -> (PeakStep, f64, f64) {
        let ts: [f64; K + 1] = std::array::from_fn(|k| t0 + h * k as f64 / K as f64);
        let mut nodes = [[0.0; MAX_DYNAMIC]; K + 1];
        let mut k_best = 0;
        for k in 0..=K {
            nodes[k][0] = f(ts[k]);
            if nodes[k][0] > nodes[k_best][0] {
                k_best = k;
            }
        }
        let step = PeakStep {
            ts,
            nodes,
            seg: Segment {
                t0: 0.0,
                x0: 0.0,
                v0: 0.0,
                a: 0.0,
                phase: crate::physics::Phase::Stopped,
            },
            regime: Regime::default(),
            k: k_best,
        };
        (step, nodes[k_best][0], nodes[K][0])
    }

    /// Observe `f` step by step over `[0, 1]` and locate its peak: `(t, value)`.
    fn peak_of(f: impl Fn(f64) -> f64) -> (f64, f64) {
        let mut c = PeakCandidate::starting_at(f(0.0), RIVAL);
        let h = 0.01;
        for i in 0..100 {
            let (step, best, end) = step_of(&f, i as f64 * h, h);
            c.observe(best, end, || step);
            if c.wants_next() {
                c.follow(step_of(&f, (i + 1) as f64 * h, h).0);
            }
        }
        let (t, v, _) = c.locate(|c, t| c.state_at(t)[0], c.best).unwrap();
        (t, v)
    }

    #[test]
    fn of_two_peaks_of_the_same_height_the_earlier_is_the_peak() {
        // two quadratic peaks (exact in the quartic nodes) at 0.2033 and 0.6913, of height 1
        // and 1 + 2e-13: the same height to the search's rounding (~1e-15) and within `TIE`,
        // though the later one is the larger and is found so (without the rule it would win)
        let bump = |t: f64, tp: f64| 1.0 - 40.0 * (t - tp) * (t - tp);
        let f = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 2e-13).max(0.0);
        let (t, v) = peak_of(f);
        assert!((t - 0.2033).abs() < 1e-6, "{t}");
        assert!((v - 1.0).abs() < 1e-14, "{v}");
        // a later peak higher by more than the tie's width is the peak
        let g = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 1e-9).max(0.0);
        let (t, _) = peak_of(g);
        assert!((t - 0.6913).abs() < 1e-6, "{t}");
    }

    #[test]
    fn a_peak_sampled_low_among_several_near_ones_is_still_found() {
        // Three sharp peaks: at 0.20125 (height 1.003, its nearest node 1.25e-3 away, so its
        // largest sample is 0.99675), at 0.4 (1.0, on a node) and at 0.601 (1.001, sample
        // 0.997). The middle one holds the largest sample; the first holds the peak, with the
        // smallest sample of the three: one rival slot would have kept the last one only.
        let bump = |t: f64, tp: f64, top: f64| top - 4000.0 * (t - tp) * (t - tp);
        let f = |t: f64| {
            bump(t, 0.20125, 1.003)
                .max(bump(t, 0.4, 1.0))
                .max(bump(t, 0.601, 1.001))
                .max(0.0)
        };
        let (t, v) = peak_of(f);
        assert!((t - 0.20125).abs() < 1e-6, "{t}");
        assert!((v - 1.003).abs() < 1e-12, "{v}");
    }

    #[test]
    fn a_higher_top_before_a_shallow_dip_is_found() {
        // Two tops 0.1 apart with a dip of 0.3 % between them (less than `RIVAL`): the first,
        // 1.25e-3 from its nearest node, is higher by 3e-6 but sampled 7.5e-6 low; the second
        // sits on a node. The second's sample is the largest, and without a dip of `RIVAL` the
        // two count as one peak: the first top's step must still be searched.
        let (left, right): (f64, f64) = (0.45125, 0.55);
        let (m, d) = (0.5 * (left + right), 0.5 * (right - left));
        let a = 0.003 / d.powi(4);
        let b = 3e-6 / (2.0 * d);
        let f = |t: f64| {
            let u = (t - m) * (t - m) - d * d;
            1.0 - a * u * u - b * (t - m)
        };
        // the true top, by a fine scan and a search around it
        let t_top = (0..=100_000)
            .map(|i| i as f64 * 1e-5)
            .max_by(|x, y| f(*x).total_cmp(&f(*y)))
            .unwrap();
        assert!((t_top - left).abs() < 1e-4, "{t_top}");
        let (_, top) = brent_max(f, t_top - 1e-4, t_top + 1e-4, (t_top, f(t_top)));
        // the larger sample is the right top's
        assert!(f(right) > f(0.4525).max(f(0.45)));
        let (t, v) = peak_of(f);
        assert!((t - t_top).abs() < 1e-5, "{t} vs {t_top}");
        assert!((v - top).abs() < 1e-13, "{v} vs {top}");
    }
}
