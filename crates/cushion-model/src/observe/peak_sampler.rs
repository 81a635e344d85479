//! The peaks of a run (`|F_r|`, `F_c`, the stroke `s`, and the gas pressure of the compressible
//! liquid), sampled at each accepted step and refined at the end of the run (`peaks.rs`).
//!
//! Each step is sampled at its end, and at three interior points of its dense output where a
//! new peak is possible; the step holding the largest sample keeps five nodes of its dense
//! output (a degree-4 polynomial, so they reproduce it exactly) and the peak inside it (or just
//! after it, in the next step, when the largest sample is the step's end) is located once, at
//! the end of the run, by Brent's search.

use crate::model::{Eval, Model, MAX_STATES};
use crate::peaks::{rival_window, PeakCandidate, PeakStep, K, MAX_DYNAMIC, TIE};
use cushion_ode::{State, Step};

/// The peaks found so far (after [`PeakSampler::refine`], the run's).
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

/// The peak observer: samples each accepted step, keeps the steps that hold the peaks.
pub(crate) struct PeakSampler {
    pub peaks: Peaks,
    fr_peak: PeakCandidate,
    fc_peak: PeakCandidate,
    s_peak: PeakCandidate,
    /// `F_r, F_c, s, sd` at the end of the last step.
    last_sample: Option<(f64, f64, f64, f64)>,
    /// Steps still to sample in full (set by events and time stops).
    force_sample: u8,
    /// The next step begins where `F_r` jumps (a robot kink under a rigid or stuck tool, a stick
    /// or slip of the tool): its start is sampled too, on its own side of the jump.
    sample_start: bool,
    /// The largest `|F_r|` of those samples, with its time (s) and sign (N).
    fr_after_jump: Option<(f64, f64)>,
}

impl PeakSampler {
    /// Start at the model's initial state; `rtol` sets how close a rival peak must come to be
    /// refined too (`peaks::rival_window`).
    pub fn new(model: &Model, rtol: f64) -> PeakSampler {
        let e0 = model.eval(0.0, &model.y0, model.robot.current(), &model.regime);
        let s0 = model.preload_stroke;
        let window = rival_window(rtol);
        PeakSampler {
            peaks: Peaks {
                peak_fr: e0.f_r,
                t_peak_fr: 0.0,
                peak_fc: e0.f_c,
                max_stroke: s0,
                max_p1: e0.p1,
            },
            fr_peak: PeakCandidate::starting_at(e0.f_r.abs(), window),
            fc_peak: PeakCandidate::starting_at(e0.f_c, window),
            s_peak: PeakCandidate::starting_at(s0, window),
            last_sample: None,
            force_sample: 0,
            sample_start: false,
            fr_after_jump: None,
        }
    }

    /// An event was handled: the next two steps are sampled in full.
    pub fn after_event(&mut self) {
        self.force_sample = 2;
    }

    /// A time stop is about to be handled (the robot's acceleration jumps there): the next two
    /// steps are sampled in full, and the next step's start too when the force on the tool
    /// jumps with the robot's acceleration (a rigid or stuck tool).
    pub fn before_time_stop(&mut self, model: &Model) {
        self.force_sample = 2;
        self.sample_start = model.tool_moves_with_robot();
    }

    /// Refine the peaks of `|F_r|`, `F_c` and `s` inside the steps that hold their largest
    /// samples (`peaks.rs`), on the step's dense output (rebuilt from its five nodes).
    pub fn refine(&mut self, model: &Model) {
        let n = model.layout.n.clamp(1, MAX_STATES);
        let (fr, fc, s) = (
            std::mem::take(&mut self.fr_peak),
            std::mem::take(&mut self.fc_peak),
            std::mem::take(&mut self.s_peak),
        );
        let at = |c: &PeakStep, t: f64| model.eval(t, &c.state_at(t)[..n], &c.seg, &c.regime);
        let m = &mut self.peaks;
        // the signed force at the refined peak, from the step that holds it (an earlier peak of
        // the same height may lie below the largest sample by rounding: `TIE`)
        let peak_fr = fr
            .locate(|c, t| at(c, t).f_r.abs(), m.peak_fr.abs())
            .filter(|&(_, v, _)| v > m.peak_fr.abs() * (1.0 - TIE))
            .map(|(t, _, c)| (t, at(c, t).f_r));
        let peak_fc = fc.locate(|c, t| at(c, t).f_c, m.peak_fc).map(|p| p.1);
        let max_stroke = s.locate(|c, t| at(c, t).s, m.max_stroke).map(|p| p.1);
        if let Some((t, f_r)) = peak_fr {
            m.peak_fr = f_r;
            m.t_peak_fr = t;
        }
        if let Some((t, f_r)) = self.fr_after_jump {
            if f_r.abs() > m.peak_fr.abs() {
                m.peak_fr = f_r;
                m.t_peak_fr = t;
            }
        }
        if let Some(v) = peak_fc {
            m.peak_fc = v;
        }
        if let Some(v) = max_stroke {
            m.max_stroke = v;
        }
    }

    /// Sample an accepted step, in the regime and robot segment it ran in (`model`'s handlers
    /// may already have moved its regime on: `Model::step_regime`).
    pub fn on_step<const N: usize>(&mut self, model: &Model, step: &Step<'_, N>) {
        let (t0, t1) = (step.t0, step.t1);
        let y1 = step.y1.as_slice();
        let seg = *model.robot.segment_at(0.5 * (t0 + t1));
        let r = *model.step_regime();
        // Five nodes of the step's dense output (a polynomial of degree 4 in t, so these five
        // states reproduce it exactly); the physics is sampled at the four after t0.
        let n = model.layout.n.clamp(1, MAX_STATES);
        let tk = |k: usize| {
            if k == K {
                t1
            } else {
                t0 + (t1 - t0) * (k as f64 / K as f64)
            }
        };
        // the states the physics reads (the ledger's quadratures come after them)
        let dynamic = model
            .layout
            .work
            .or(model.layout.contact_impulse)
            .unwrap_or(n)
            .min(MAX_DYNAMIC);
        // a node: the leading `dynamic` states (a fixed-length loop: no call to memcpy)
        let lead = |yk: &State<N>| {
            let mut v = [0.0; MAX_DYNAMIC];
            for (j, vj) in v.iter_mut().enumerate().take(N.min(MAX_DYNAMIC)) {
                if j < dynamic {
                    *vj = yk[j];
                }
            }
            v
        };
        let node = |k: usize| match k {
            0 => lead(step.y0),
            K => lead(step.y1),
            _ => lead(&step.at(tk(k))),
        };
        let mut fr_best = (0usize, 0.0f64);
        let mut fc_best = (0usize, 0.0f64);
        let mut s_best = (0usize, f64::NEG_INFINITY);
        let mut p1_best = f64::NEG_INFINITY;
        let mut consider = |k: usize, e: &Eval| {
            if e.p1 > p1_best {
                p1_best = e.p1;
            }
            if e.f_r.abs() > fr_best.1.abs() {
                fr_best = (k, e.f_r);
            }
            if e.f_c > fc_best.1 {
                fc_best = (k, e.f_c);
            }
            if e.s > s_best.1 {
                s_best = (k, e.s);
            }
        };
        let e1 = model.eval_inline(t1, y1, &seg, &r);
        consider(K, &e1);
        if std::mem::take(&mut self.sample_start) {
            // Where the step begins, the force on a rigid or stuck tool jumps by `m_t` times
            // the jump of the robot's acceleration, and a stick or slip changes the friction:
            // the largest |F_r| may be the first value on this side, which no sample inside
            // the step sees (a rigid tool still pressing an object when the robot stops
            // braking: `F_r` jumps by `m_t a_brake` there and falls after;
            // `tests/peaks.rs::a_force_that_jumps_when_the_robot_stops_is_its_peak`). It is
            // kept apart from the peak search: a value at a jump is exact where it is.
            let f_r = model.eval_inline(t0, step.y0.as_slice(), &seg, &r).f_r;
            if self.fr_after_jump.is_none_or(|(_, f)| f_r.abs() > f.abs()) {
                self.fr_after_jump = Some((t0, f_r));
            }
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
        // The nodes of a new peak candidate, computed at most once per step (below).
        let mut nodes: Option<[[f64; MAX_DYNAMIC]; K + 1]> = None;
        if interior {
            // the interior samples are the interior nodes
            let mut v = [[0.0; MAX_DYNAMIC]; K + 1];
            v[0] = node(0);
            v[K] = node(K);
            for (k, vk) in v.iter_mut().enumerate().take(K).skip(1) {
                let yk = step.at(tk(k));
                *vk = lead(&yk);
                let e = model.eval_inline(tk(k), yk.as_slice(), &seg, &r);
                consider(k, &e);
            }
            nodes = Some(v);
        }
        self.last_sample = Some((e1.f_r, e1.f_c, e1.s, e1.sd));
        if p1_best > self.peaks.max_p1 {
            self.peaks.max_p1 = p1_best;
        }
        self.force_sample = self.force_sample.saturating_sub(1);
        // A new largest sample: remember its step; the peak inside it is refined once, at the
        // end of the run (`refine`).
        let mut cand = |k: usize| PeakStep {
            ts: std::array::from_fn(tk),
            nodes: *nodes.get_or_insert_with(|| std::array::from_fn(node)),
            seg,
            regime: r,
            k,
        };
        // A largest sample at the previous step's end: the peak may lie in this step.
        for c in [&mut self.fr_peak, &mut self.fc_peak, &mut self.s_peak] {
            if c.wants_next() {
                c.follow(cand(0));
            }
        }
        let (v, end) = (fr_best.1.abs(), e1.f_r.abs());
        if self.fr_peak.observe(v, end, || cand(fr_best.0)) {
            self.peaks.peak_fr = fr_best.1;
            self.peaks.t_peak_fr = tk(fr_best.0);
        }
        if self.fc_peak.observe(fc_best.1, e1.f_c, || cand(fc_best.0)) {
            self.peaks.peak_fc = fc_best.1;
        }
        if model.layout.tool.is_some() && self.s_peak.observe(s_best.1, e1.s, || cand(s_best.0)) {
            self.peaks.max_stroke = s_best.1;
        }
        // a stick or slip of the tool, or a slip that turns, changes its friction at once
        let (now, then) = (&model.regime, &r);
        if now.tool_stuck != then.tool_stuck || now.tool_dir != then.tool_dir {
            self.sample_start = true;
        }
    }
}
