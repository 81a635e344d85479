//! The peaks of a run (`|F_r|`, `F_c`, the stroke `s`, and the gas pressure of the compressible
//! liquid), sampled at each accepted step, each local top near the largest value searched on
//! the dense output at once (`search.rs`).
//!
//! Each step is sampled at its end, and at three interior points of its dense output where a
//! new peak is possible. A top inside the step is searched on the step's own dense output; a
//! top at its end, once the next step's first sample confirms it, on both steps (the step is
//! kept until then).

use super::kept_step::KeptStep;
use super::search::locate_on;
use super::top_step::Unstable;
use super::tracker::{top_window, Peak, PeakTracker};
use crate::model::{Eval, Model, Regime};
use crate::physics::Segment;
use cushion_ode::{Observer, Step};

/// Samples of the physics per step (besides its start).
pub(crate) const K: usize = 4;

/// The peaks found so far (after [`PeakSampler::finish`], the run's).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Peaks {
    /// Robot force at the largest `|F_r|` (signed, N) and its time (s).
    pub peak_fr: f64,
    pub t_peak_fr: f64,
    /// Largest contact force (N).
    pub peak_fc: f64,
    /// Largest stroke (m).
    pub max_stroke: f64,
    /// Largest sampled gas pressure (Pa; compressible model: the lumped one uses
    /// `p1(max_stroke)`).
    pub max_p1: f64,
}

/// A quantity whose peak is found: its value in an evaluation of the physics, and what is
/// reported for it (the signed force where the value is `|F_r|`).
type Quantity = fn(&Eval) -> (f64, f64);

/// `|F_r|`, `F_c` and the stroke, in the order of [`PeakSampler::trackers`].
const QUANTITIES: [Quantity; 3] = [|e| (e.f_r.abs(), e.f_r), |e| (e.f_c, e.f_c), |e| (e.s, e.s)];
const ROBOT_FORCE: usize = 0;
const STROKE: usize = 2;
/// Which of [`QUANTITIES`] carry a fast mode's velocity, and are searched on a step integrated
/// again in halves where its dense output is not stable (`top_step.rs`): the forces, through
/// the orifice's `v |v|` and the contacts' damping. The stroke is a position, which sees only
/// the integral of that deviation over the step: on its own dense output it stays within the
/// tolerance (on the design space under DOP853 its errors are the same either way: 1.2e-3 at
/// worst, on strokes of nanometres; 6e-5 at rtol 1e-4 on paper-hydraulic-dt70, 1.4e-6 on the
/// halves).
const FAST: [bool; 3] = [true, true, false];

/// One sample of the physics: what the peaks read (kept whole, an `Eval` would have all its
/// fields computed).
#[derive(Clone, Copy, Debug)]
struct Sampled {
    t: f64,
    /// The value of each of [`QUANTITIES`].
    values: [f64; 3],
    p1: f64,
}

/// The peak observer: samples each accepted step and searches the tops near the peaks.
pub(crate) struct PeakSampler {
    /// The largest values so far, samples or located (what the early end and the sampling
    /// rule compare with; `peak_fr` is then the largest `|F_r|`, its sign comes at the end);
    /// after [`PeakSampler::finish`], the located peaks.
    pub peaks: Peaks,
    /// One per quantity of [`QUANTITIES`].
    trackers: [PeakTracker; 3],
    /// The last step, while a sample at its end may be a top.
    kept: Option<KeptStep>,
    /// `F_r, F_c, s, sd` at the end of the last step.
    last_sample: Option<(f64, f64, f64, f64)>,
    /// Steps still to sample in full (set by events and time stops).
    force_sample: u8,
    /// The next step begins where `F_r` jumps (a robot kink under a rigid or stuck tool, a stick
    /// or slip of the tool): its start is sampled too, on its own side of the jump.
    sample_start: bool,
    /// The evaluations of `f` the halves took (the run counts them with the solver's).
    pub halves_evals: u64,
}

impl PeakSampler {
    /// Start at the model's initial state; `rtol` sets how near the peak so far a top must come
    /// to be searched (`peaks::top_window`).
    pub fn new(model: &Model, rtol: f64) -> PeakSampler {
        let e0 = model.eval(0.0, &model.y0, model.robot.current(), &model.regime);
        let s0 = model.preload_stroke;
        let window = top_window(rtol);
        let start = |value: f64, reported: f64| {
            let p = Peak {
                t: 0.0,
                value,
                reported,
            };
            PeakTracker::starting_at(p, window)
        };
        PeakSampler {
            peaks: Peaks {
                peak_fr: e0.f_r,
                t_peak_fr: 0.0,
                peak_fc: e0.f_c,
                max_stroke: s0,
                max_p1: e0.p1,
            },
            trackers: [
                start(e0.f_r.abs(), e0.f_r),
                start(e0.f_c, e0.f_c),
                start(s0, s0),
            ],
            kept: None,
            last_sample: None,
            force_sample: 0,
            sample_start: false,
            halves_evals: 0,
        }
    }

    /// A time stop is about to be handled (the robot's acceleration jumps there): the next two
    /// steps are sampled in full, and the next step's start too when the force on the tool
    /// jumps with the robot's acceleration (a rigid or stuck tool).
    pub fn time_stop_ahead(&mut self, model: &Model) {
        self.force_sample = 2;
        self.sample_start = model.tool_moves_with_robot();
    }

    /// The run has ended: a quantity still rising at the last step's end has its top there (or
    /// just before it, in the last step); the peaks become the located ones.
    pub fn finish(&mut self, model: &Model) {
        if let Some(c) = self.kept.take() {
            let at = |t: f64| c.eval(model, t);
            let unstable_kept = (!c.dense_stable).then_some(&c);
            let mut unstable = Unstable::new(model, None, unstable_kept);
            let tracked = tracked(model);
            for (i, (tr, q)) in self
                .trackers
                .iter_mut()
                .zip(QUANTITIES)
                .enumerate()
                .take(tracked)
            {
                if let Some(b) = tr.open_top() {
                    if unstable_kept.is_some() && FAST[i] {
                        let span = (f64::INFINITY, f64::INFINITY);
                        tr.found(unstable.locate(b, span, q, at, at));
                        continue;
                    }
                    tr.found(locate_on(b, f64::INFINITY, q, at, at));
                }
            }
            self.halves_evals += unstable.evals;
        }
        let [fr, fc, s] = &self.trackers;
        let m = &mut self.peaks;
        m.peak_fr = fr.peak.reported;
        m.t_peak_fr = fr.peak.t;
        m.peak_fc = fc.peak.value;
        m.max_stroke = s.peak.value;
    }

    /// Sample an accepted step, in the regime and robot segment it ran in (`model`'s handlers
    /// may already have moved its regime on: `Model::step_regime`).
    fn sample<const N: usize>(&mut self, model: &Model, step: &Step<'_, N>) {
        let (t0, t1) = (step.t0, step.t1);
        let y1 = step.y1.as_slice();
        let seg = *model.robot.segment_at(0.5 * (t0 + t1));
        let r = *model.step_regime();
        let tk = |k: usize| {
            if k == K {
                t1
            } else {
                t0 + (t1 - t0) * (k as f64 / K as f64)
            }
        };
        let e1 = model.eval_inline(t1, y1, &seg, &r);
        if std::mem::take(&mut self.sample_start) {
            // Where the step begins, the force on a rigid or stuck tool jumps by `m_t` times
            // the jump of the robot's acceleration, and a stick or slip changes the friction:
            // the largest |F_r| may be the first value on this side, which no sample inside
            // the step sees (a rigid tool still pressing an object when the robot stops
            // braking: `F_r` jumps by `m_t a_brake` there and falls after;
            // `tests/model/peaks.rs::a_force_that_jumps_when_the_robot_stops_is_its_peak`). A
            // value at a jump is exact where it is: it is found, not searched.
            let f_r = model.eval_inline(t0, step.y0.as_slice(), &seg, &r).f_r;
            self.trackers[ROBOT_FORCE].found(Peak {
                t: t0,
                value: f_r.abs(),
                reported: f_r,
            });
        }
        // The interior is sampled only where a new peak is possible: near or above the force
        // peaks so far, where the stroke turns (its largest value lies in a step where `sd`
        // changes sign; while it rises, the step's end is its largest), and around events;
        // elsewhere the step's end suffices.
        let m = &self.peaks;
        let interior = match self.last_sample {
            None => true,
            Some((fr0, fc0, _, sd0)) => {
                self.force_sample > 0
                    || fr0.abs().max(e1.f_r.abs()) > 0.5 * m.peak_fr.abs()
                    || fc0.max(e1.f_c) > 0.5 * m.peak_fc
                    || (sd0 > 0.0 && e1.sd <= 0.0)
            }
        };
        // the samples, in time order
        let pick = |t: f64, e: &Eval| Sampled {
            t,
            values: QUANTITIES.map(|q| q(e).0),
            p1: e.p1,
        };
        let end = pick(t1, &e1);
        let mut samples = [end; K];
        let mut count = 0;
        if interior {
            for k in 1..K {
                let t = tk(k);
                samples[count] = pick(t, &model.eval_inline(t, step.at(t).as_slice(), &seg, &r));
                count += 1;
            }
        }
        samples[count] = end;
        count += 1;
        let samples = &samples[..count];
        self.last_sample = Some((e1.f_r, e1.f_c, e1.s, e1.sd));
        self.force_sample = self.force_sample.saturating_sub(1);

        // Each quantity's samples in turn; a top they confirm is searched at once, on this
        // step's dense output and, for a top at its start, the kept step's before it (a top at
        // the start confirmed by this step's samples was a candidate at the end of the last
        // one, under the same test: that step is kept).
        let tracked = tracked(model);
        let unstable = !step.dense_stable || self.kept.as_ref().is_some_and(|c| !c.dense_stable);
        if unstable {
            self.locate_tops_near_unstable(model, step, (&seg, &r), samples, tracked);
        } else {
            let (here, behind) = on_dense(model, step, (&seg, &r), &self.kept);
            for (i, tr) in self.trackers.iter_mut().enumerate().take(tracked) {
                for p in samples {
                    if let Some(b) = tr.sample(p.t, p.values[i]) {
                        tr.found(locate_on(b, t0, QUANTITIES[i], here, behind));
                    }
                }
            }
        }
        // the largest values so far, for the sampling rule above and the early end
        let m = &mut self.peaks;
        for p in samples {
            if p.p1 > m.max_p1 {
                m.max_p1 = p.p1;
            }
        }
        let [fr, fc, s] = &self.trackers;
        m.peak_fr = fr.largest();
        m.peak_fc = fc.largest();
        m.max_stroke = s.largest();
        // a sample at the step's end may be a top: keep the step until the next one shows
        let may_top = self.trackers[..tracked].iter().any(PeakTracker::may_top);
        // (overwritten in place: it is kept on most steps near a peak)
        match (&mut self.kept, may_top) {
            (Some(k), true) => {
                step.dense.leading_into(&mut k.dense);
                k.seg = seg;
                k.regime = r;
                k.dense_stable = step.dense_stable;
            }
            (None, true) => {
                self.kept = Some(KeptStep {
                    dense: step.dense.leading(),
                    seg,
                    regime: r,
                    dense_stable: step.dense_stable,
                })
            }
            (_, false) => self.kept = None,
        }
        // a stick or slip of the tool, or a slip that turns, changes its friction at once
        let (now, then) = (&model.regime, &r);
        if now.tool_stuck != then.tool_stuck || now.tool_dir != then.tool_dir {
            self.sample_start = true;
        }
    }

    /// [`PeakSampler::on_step`]'s search of the tops its samples confirm, where the dense
    /// output of this step or of the kept one before it is not stable: a force's top whose
    /// bracket reaches into such a step is searched on it integrated again in halves
    /// (`top_step.rs`, [`FAST`]), made once, at the first top that needs it.
    #[cold]
    #[inline(never)]
    fn locate_tops_near_unstable<const N: usize>(
        &mut self,
        model: &Model,
        step: &Step<'_, N>,
        (seg, r): (&Segment, &Regime),
        samples: &[Sampled],
        tracked: usize,
    ) {
        let (t0, t1) = (step.t0, step.t1);
        let (here, behind) = on_dense(model, step, (seg, r), &self.kept);
        let here_unstable = !step.dense_stable;
        let kept_unstable = self.kept.as_ref().filter(|c| !c.dense_stable);
        let this = || KeptStep {
            dense: step.dense.leading(),
            seg: *seg,
            regime: *r,
            dense_stable: false,
        };
        let mut unstable: Option<Unstable> = None;
        for (i, tr) in self.trackers.iter_mut().enumerate().take(tracked) {
            for p in samples {
                if let Some(b) = tr.sample(p.t, p.values[i]) {
                    let reaches = here_unstable || (b.lo < t0 && kept_unstable.is_some());
                    let top = if FAST[i] && reaches {
                        unstable
                            .get_or_insert_with(|| {
                                Unstable::new(model, here_unstable.then(this), kept_unstable)
                            })
                            .locate(b, (t0, t1), QUANTITIES[i], here, behind)
                    } else {
                        locate_on(b, t0, QUANTITIES[i], here, behind)
                    };
                    tr.found(top);
                }
            }
        }
        if let Some(u) = unstable {
            self.halves_evals += u.evals;
        }
    }
}

/// The peak sampler watches every run: each accepted step is sampled, and after an event or
/// before a time stop the next steps in full.
impl<const N: usize> Observer<Model, N> for PeakSampler {
    #[inline]
    fn on_step(&mut self, model: &Model, step: &Step<'_, N>) {
        self.sample(model, step);
    }

    #[inline]
    fn after_events(&mut self, _model: &Model) {
        self.force_sample = 2;
    }

    #[inline]
    fn before_time_stop(&mut self, model: &Model) {
        self.time_stop_ahead(model);
    }
}

/// The physics on the current step's dense output, and on the kept step's before it (the
/// current one's where none is kept).
#[inline(always)]
fn on_dense<'a, const N: usize>(
    model: &'a Model,
    step: &'a Step<'_, N>,
    (seg, r): (&'a Segment, &'a Regime),
    kept: &'a Option<KeptStep>,
) -> (
    impl Fn(f64) -> Eval + Copy + 'a,
    impl Fn(f64) -> Eval + Copy + 'a,
) {
    let here = move |t: f64| model.eval(t, step.at(t).as_slice(), seg, r);
    let behind = move |t: f64| match kept {
        Some(c) => c.eval(model, t),
        None => here(t),
    };
    (here, behind)
}

/// How many of [`QUANTITIES`] a run tracks: the stroke only where there is a tool.
fn tracked(model: &Model) -> usize {
    if model.layout.tool.is_some() {
        QUANTITIES.len()
    } else {
        // the stroke comes last: the ones before it
        STROKE
    }
}
