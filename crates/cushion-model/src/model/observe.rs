//! What each accepted step tells the summary: the peaks' samples at its end and inside it, and
//! the peaks refined at the end of the run (`peaks.rs`). The trajectory is recorded apart
//! (`recorder.rs`).

use super::{Eval, Model, MAX_STATES};
use crate::peaks::{PeakStep, K, MAX_DYNAMIC, TIE};
use cushion_ode::{Control, State, Step};

impl Model {
    /// Refine the peaks of `|F_r|`, `F_c` and `s` inside the steps that hold their largest
    /// samples (`peaks.rs`), on the step's dense output (rebuilt from its five nodes).
    pub(crate) fn refine_peaks(&mut self) {
        let n = self.layout.n.clamp(1, MAX_STATES);
        let (fr, fc, s) = (
            std::mem::take(&mut self.fr_peak),
            std::mem::take(&mut self.fc_peak),
            std::mem::take(&mut self.s_peak),
        );
        let at = |c: &PeakStep, t: f64| self.eval(t, &c.state_at(t)[..n], &c.seg, &c.regime);
        let m = &self.metrics;
        // the signed force at the refined peak, from the step that holds it (an earlier peak of
        // the same height may lie below the largest sample by rounding: `TIE`)
        let peak_fr = fr
            .locate(|c, t| at(c, t).f_r.abs(), m.peak_fr.abs())
            .filter(|&(_, v, _)| v > m.peak_fr.abs() * (1.0 - TIE))
            .map(|(t, _, c)| (t, at(c, t).f_r));
        let peak_fc = fc.locate(|c, t| at(c, t).f_c, m.peak_fc).map(|p| p.1);
        let max_stroke = s.locate(|c, t| at(c, t).s, m.max_stroke).map(|p| p.1);
        if let Some((t, f_r)) = peak_fr {
            self.metrics.peak_fr = f_r;
            self.metrics.t_peak_fr = t;
        }
        if let Some((t, f_r)) = self.fr_after_jump {
            if f_r.abs() > self.metrics.peak_fr.abs() {
                self.metrics.peak_fr = f_r;
                self.metrics.t_peak_fr = t;
            }
        }
        if let Some(v) = peak_fc {
            self.metrics.peak_fc = v;
        }
        if let Some(v) = max_stroke {
            self.metrics.max_stroke = v;
        }
    }

    pub(super) fn observe_step<const N: usize>(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        let (t0, t1) = (step.t0, step.t1);
        let y1 = step.y1.as_slice();
        let seg = *self.robot.segment_at(0.5 * (t0 + t1));
        let r = self.step_regime;
        // Five nodes of the step's dense output (a polynomial of degree 4 in t, so these five
        // states reproduce it exactly); the physics is sampled at the four after t0.
        let n = self.layout.n.clamp(1, MAX_STATES);
        let tk = |k: usize| {
            if k == K {
                t1
            } else {
                t0 + (t1 - t0) * (k as f64 / K as f64)
            }
        };
        // the states the physics reads (the ledger's quadratures come after them)
        let dynamic = self
            .layout
            .work
            .or(self.layout.contact_impulse)
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
        let e1 = self.eval_inline(t1, y1, &seg, &r);
        consider(K, &e1);
        if std::mem::take(&mut self.sample_start) {
            // Where the step begins, the force on a rigid or stuck tool jumps by `m_t` times
            // the jump of the robot's acceleration, and a stick or slip changes the friction:
            // the largest |F_r| may be the first value on this side, which no sample inside
            // the step sees (a rigid tool still pressing an object when the robot stops
            // braking: `F_r` jumps by `m_t a_brake` there and falls after;
            // `tests/peaks.rs::a_force_that_jumps_when_the_robot_stops_is_its_peak`). It is
            // kept apart from the peak search: a value at a jump is exact where it is.
            let f_r = self.eval_inline(t0, step.y0.as_slice(), &seg, &r).f_r;
            if self.fr_after_jump.is_none_or(|(_, f)| f_r.abs() > f.abs()) {
                self.fr_after_jump = Some((t0, f_r));
            }
        }
        // The interior is sampled only where a new peak is possible: near or above the force
        // peaks so far, where the stroke turns (its largest value lies in a step where `sd`
        // changes sign; while it rises, the step's end is its largest), and around events;
        // elsewhere the step's end suffices.
        let m = &self.metrics;
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
                let e = self.eval_inline(tk(k), yk.as_slice(), &seg, &r);
                consider(k, &e);
            }
            nodes = Some(v);
        }
        self.last_sample = Some((e1.f_r, e1.f_c, e1.s, e1.sd));
        if p1_best > self.metrics.max_p1 {
            self.metrics.max_p1 = p1_best;
        }
        self.force_sample = self.force_sample.saturating_sub(1);
        // A new largest sample: remember its step; the peak inside it is refined once, at the
        // end of the run (`refine_peaks`).
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
            self.metrics.peak_fr = fr_best.1;
            self.metrics.t_peak_fr = tk(fr_best.0);
        }
        if self.fc_peak.observe(fc_best.1, e1.f_c, || cand(fc_best.0)) {
            self.metrics.peak_fc = fc_best.1;
        }
        if self.layout.tool.is_some() && self.s_peak.observe(s_best.1, e1.s, || cand(s_best.0)) {
            self.metrics.max_stroke = s_best.1;
        }
        // a stick or slip of the tool, or a slip that turns, changes its friction at once
        if self.regime.tool_stuck != r.tool_stuck || self.regime.tool_dir != r.tool_dir {
            self.sample_start = true;
        }
        self.step_regime = self.regime;

        // Early end: nothing can change any more.
        if self.can_end_early(t1, y1) {
            self.early_end = Some(t1);
            ctl.stop();
        }
    }
}
