//! The integration loop: step, control, events, time stops, output. It orchestrates; each of
//! those ideas lives in its own file.

use crate::controller::{initial_step, PiController};
use crate::dense::DenseOutput;
use crate::dopri5::Dopri5;
use crate::events::locate;
use crate::norm::Weights;
use crate::options::{Method, Output, SolverOptions, StiffnessAction, Tolerance};
use crate::solution::{EventRecord, Solution, Stats, Status};
use crate::stepper::{ExplicitRk, Stepper};
use crate::stiffness::StiffnessDetector;
use crate::system::{Control, Direction, EventAction, OdeSystem, Step, MAX_EVENTS};
use crate::tableau::{CLASSICAL_RK4, EXPLICIT_EULER};
use crate::State;

/// Integrate `sys` from `(t0, y0)` to `t_end` with the settings `opts`. Never panics on bad
/// numbers: it returns a [`Solution`] whose status says how it ended.
pub fn solve<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t0: f64,
    y0: State<N>,
    t_end: f64,
    opts: &SolverOptions,
) -> Solution<N> {
    let integration = Integration::new(sys, t0, y0, t_end, opts);
    match opts.method {
        // The hot path: DOPRI5 with constant coefficients (same numbers as its tableau).
        Method::Dp5 => integration.run(&mut Dopri5::<N>::new()),
        Method::Rk4 => integration.run(&mut ExplicitRk::<N>::new(&CLASSICAL_RK4)),
        Method::Euler => integration.run(&mut ExplicitRk::<N>::new(&EXPLICIT_EULER)),
    }
}

/// Check the settings; `Err` holds the message of an `InvalidInput` status.
fn check_options<const N: usize>(
    t0: f64,
    y0: &State<N>,
    t_end: f64,
    opts: &SolverOptions,
    n_events: usize,
) -> Result<(), String> {
    let tol_ok = |name: &str, tol: &Tolerance, allow_zero: bool| -> Result<(), String> {
        if let Tolerance::PerComponent(v) = tol {
            if v.len() != N {
                return Err(format!(
                    "{name} has {} components, the state has {N}",
                    v.len()
                ));
            }
        }
        for i in 0..N {
            let x = tol.get(i);
            let bad = !x.is_finite() || x < 0.0 || (!allow_zero && x == 0.0);
            if bad {
                return Err(format!("{name}[{i}] = {x}: must be a finite number > 0"));
            }
        }
        Ok(())
    };
    tol_ok("rtol", &opts.rtol, true)?;
    tol_ok("atol", &opts.atol, true)?;
    if (0..N).any(|i| opts.rtol.get(i) == 0.0 && opts.atol.get(i) == 0.0) {
        return Err("rtol and atol are both zero for a component".into());
    }
    if !t0.is_finite() || !t_end.is_finite() || t_end < t0 {
        return Err(format!(
            "t0 = {t0}, t_end = {t_end}: need finite t0 <= t_end"
        ));
    }
    if !(opts.h_max > 0.0) {
        return Err(format!("h_max = {}: must be > 0", opts.h_max));
    }
    if let Some(h0) = opts.h0 {
        if !(h0 > 0.0 && h0.is_finite()) {
            return Err(format!("h0 = {h0}: must be a finite number > 0"));
        }
    }
    if !opts.method.is_adaptive() && !(opts.fixed_step > 0.0 && opts.fixed_step.is_finite()) {
        return Err(format!(
            "fixed_step = {}: must be a finite number > 0",
            opts.fixed_step
        ));
    }
    if n_events > MAX_EVENTS {
        return Err(format!("{n_events} event functions: at most {MAX_EVENTS}"));
    }
    if !(0.0 < opts.min_ratio
        && opts.min_ratio < 1.0
        && opts.max_ratio > 1.0
        && opts.safety > 0.0
        && opts.safety <= 1.0)
    {
        return Err("step controller settings out of range".into());
    }
    if !y0.iter().all(|v| v.is_finite()) {
        return Err("the initial state is not finite".into());
    }
    Ok(())
}

/// Interior event-scan fractions computed in advance; more subdivisions than this (unusual) are
/// divided on the fly.
const MAX_PRECOMPUTED_FRACTIONS: usize = 64;

struct Integration<'a, S, const N: usize> {
    sys: &'a mut S,
    opts: &'a SolverOptions,
    t_end: f64,
    t: f64,
    y: State<N>,
    f: State<N>,
    stats: Stats,
    weights: Weights<N>,
    /// Pending time stops, ascending, all > t.
    stops: Vec<f64>,
    n_events: usize,
    g: [f64; MAX_EVENTS],
    /// `k / segments` for the first interior event-scan points `k = 1, 2, ...`, divided once
    /// here rather than every step (the same numbers).
    scan_fractions: Vec<f64>,
    events: Vec<EventRecord<N>>,
    ts: Vec<f64>,
    ys: Vec<State<N>>,
    next_output: usize,
}

impl<'a, S: OdeSystem<N>, const N: usize> Integration<'a, S, N> {
    fn new(sys: &'a mut S, t0: f64, y0: State<N>, t_end: f64, opts: &'a SolverOptions) -> Self {
        let mut rtol = State::<N>::zeros();
        let mut atol = State::<N>::zeros();
        for i in 0..N {
            rtol[i] = opts.rtol.get(i);
            atol[i] = opts.atol.get(i);
        }
        let n_events = sys.event_count();
        let mut stops: Vec<f64> = opts
            .time_stops
            .iter()
            .copied()
            .filter(|&s| s > t0 && s < t_end)
            .collect();
        stops.sort_by(|a, b| a.total_cmp(b));
        stops.dedup();
        stops.reserve(16);
        let segments = opts.event_subdivisions.saturating_add(1);
        let scan_fractions = if n_events == 0 {
            Vec::new()
        } else {
            (1..segments.min(MAX_PRECOMPUTED_FRACTIONS + 1))
                .map(|k| k as f64 / segments as f64)
                .collect()
        };
        Integration {
            sys,
            opts,
            t_end,
            t: t0,
            y: y0,
            f: State::<N>::zeros(),
            stats: Stats::default(),
            weights: Weights { rtol, atol },
            stops,
            n_events,
            g: [0.0; MAX_EVENTS],
            scan_fractions,
            events: Vec::with_capacity(64),
            ts: Vec::new(),
            ys: Vec::new(),
            next_output: 0,
        }
    }

    fn finish(self, status: Status, message: impl Into<String>) -> Solution<N> {
        Solution {
            status,
            message: message.into(),
            t: self.t,
            y: self.y,
            ts: self.ts,
            ys: self.ys,
            events: self.events,
            stats: self.stats,
        }
    }

    #[inline]
    fn rhs(&mut self, t: f64, y: &State<N>) -> State<N> {
        self.stats.rhs_evals += 1;
        self.sys.rhs(t, y)
    }

    fn eval_events(&self, t: f64, y: &State<N>, g: &mut [f64; MAX_EVENTS]) {
        if self.n_events > 0 {
            self.sys.events(t, y, &mut g[..self.n_events]);
        }
    }

    /// Apply time stops a handler asked for.
    fn take_new_stops(&mut self, ctl: &mut Control) {
        for &s in &ctl.new_time_stops[..ctl.n_new_time_stops] {
            if s > self.t && s < self.t_end && s.is_finite() && !self.stops.contains(&s) {
                let pos = self.stops.partition_point(|&x| x < s);
                self.stops.insert(pos, s);
            }
        }
        ctl.n_new_time_stops = 0;
    }

    /// Record the requested output points in `(t0, t1]` (and `t0` itself at the start).
    fn record_output(&mut self, dense: Option<&DenseOutput<N>>, t1: f64, y1: &State<N>) {
        match &self.opts.output {
            Output::None => {}
            Output::Steps => {
                self.ts.push(t1);
                self.ys.push(*y1);
            }
            Output::Times(times) => {
                while self.next_output < times.len() && times[self.next_output] <= t1 {
                    let tr = times[self.next_output];
                    if tr >= self.t {
                        let yr = if tr == t1 {
                            *y1
                        } else {
                            match dense {
                                Some(d) => d.eval(tr),
                                None => *y1,
                            }
                        };
                        self.ts.push(tr);
                        self.ys.push(yr);
                    }
                    self.next_output += 1;
                }
            }
        }
    }

    fn run<M: Stepper<N>>(mut self, stepper: &mut M) -> Solution<N> {
        if let Err(msg) = check_options(self.t, &self.y, self.t_end, self.opts, self.n_events) {
            return self.finish(Status::InvalidInput, msg);
        }
        let (y0, t0) = (self.y, self.t);
        self.f = self.rhs(t0, &y0);
        if let Output::Steps = self.opts.output {
            self.ts.push(t0);
            self.ys.push(y0);
        } else {
            self.record_output(None, t0, &y0);
        }
        if !self.f.iter().all(|v| v.is_finite()) {
            return self.finish(
                Status::NonFinite,
                format!("f(t0, y0) is not finite at t = {t0}"),
            );
        }
        let mut g0 = [0.0; MAX_EVENTS];
        self.eval_events(t0, &y0, &mut g0);
        self.g = g0;
        if self.t_end == t0 {
            return self.finish(Status::Success, "");
        }

        let adaptive = stepper.is_adaptive();
        let h_max = self.opts.h_max.min(self.t_end - t0);
        let mut controller = PiController::new(
            stepper.order(),
            self.opts.safety,
            self.opts.beta,
            self.opts.min_ratio,
            self.opts.max_ratio,
        );
        let mut stiffness = StiffnessDetector::default();
        let mut h = if !adaptive {
            self.opts.fixed_step
        } else {
            match self.opts.h0 {
                Some(h0) => h0.min(h_max),
                None => self.select_step(stepper.order(), h_max),
            }
        };
        let mut ctl = Control::new();

        loop {
            if self.stats.steps + self.stats.rejected >= self.opts.max_steps {
                let msg = format!(
                    "step limit {} reached at t = {}",
                    self.opts.max_steps, self.t
                );
                return self.finish(Status::MaxSteps, msg);
            }
            // The next point the step must land on exactly.
            let next_stop = self
                .stops
                .first()
                .copied()
                .unwrap_or(self.t_end)
                .min(self.t_end);
            if adaptive {
                h = h.min(h_max);
            } else {
                h = self.opts.fixed_step;
            }
            let mut landing = false;
            if self.t + 1.01 * h >= next_stop {
                h = next_stop - self.t;
                landing = true;
            }
            if 0.1 * h.abs() <= self.t.abs() * f64::EPSILON || h <= 0.0 {
                let msg = format!("step size too small: h = {h:e} at t = {}", self.t);
                return self.finish(Status::StepTooSmall, msg);
            }

            let (t, y, f0) = (self.t, self.y, self.f);
            let attempt = stepper.step(&*self.sys, t, &y, &f0, h);
            self.stats.rhs_evals += stepper.rhs_evals_per_step();
            let finite = attempt.y1.iter().all(|v| v.is_finite())
                && attempt.f1.iter().all(|v| v.is_finite())
                && attempt.err.is_none_or(|e| e.iter().all(|v| v.is_finite()));
            if !finite {
                if !adaptive {
                    let msg =
                        format!("non-finite state in the step from t = {t} (fixed step {h:e})");
                    return self.finish(Status::NonFinite, msg);
                }
                self.stats.rejected += 1;
                h = controller.reject_non_finite(h);
                continue;
            }
            let mut h_new = h;
            if let Some(err) = &attempt.err {
                let en = self.weights.error_norm(err, &y, &attempt.y1);
                let (accepted, hn) = controller.next(en, h);
                if !accepted {
                    self.stats.rejected += 1;
                    h = hn;
                    continue;
                }
                h_new = hn;
            }
            self.stats.steps += 1;

            // Stiffness test.
            if self.opts.stiffness != StiffnessAction::Off {
                if let Some(hl) = stepper.stiffness_estimate(h, &attempt.y1, &attempt.f1) {
                    if let Some(since) = stiffness.observe(t, hl) {
                        if !self.stats.stiff {
                            self.stats.stiff = true;
                            self.stats.stiff_since = Some(since);
                        }
                        if self.opts.stiffness == StiffnessAction::Stop {
                            self.t = t + h;
                            self.y = attempt.y1;
                            let msg = format!(
                                "the problem is stiff since t = {since} (h*lambda > {:.3} for {} steps)",
                                crate::stiffness::THRESHOLD,
                                crate::stiffness::STIFF_STEPS
                            );
                            return self.finish(Status::Stiff, msg);
                        }
                    }
                }
            }

            let t1 = if landing { next_stop } else { t + h };
            let dense = stepper.dense(t, t1 - t, &y, &attempt.y1, &f0, &attempt.f1);

            // Events inside (t, t1].
            let (t_cut, y_cut, action) = self.scan_events(&dense, t, t1, &attempt.y1, &mut ctl);
            let cut = action != EventAction::Continue;
            let (t_new, mut y_new) = if cut {
                (t_cut, y_cut)
            } else {
                (t1, attempt.y1)
            };

            // The step as it ended, before any handler changed the state.
            let y_end = if cut { dense.eval(t_new) } else { y_new };
            self.record_output(Some(&dense), t_new, &y_end);
            self.sys.on_step(
                &Step {
                    t0: t,
                    t1: t_new,
                    y0: &y,
                    y1: &y_end,
                    dense: &dense,
                },
                &mut ctl,
            );
            self.t = t_new;
            self.y = y_new;
            self.take_new_stops(&mut ctl);

            if action == EventAction::Stop || ctl.stop_requested {
                return self.finish(Status::StoppedByEvent, "");
            }
            if cut {
                // State or regime changed: evaluate f anew and select the step size anew.
                if !self.restart_at(t_new, &y_new) {
                    return self.finish(
                        Status::NonFinite,
                        format!("f is not finite after the event at t = {t_new}"),
                    );
                }
                if adaptive {
                    controller.reset();
                    h = self.select_step(stepper.order(), h_max).min(h_new.max(h));
                }
                continue;
            }
            self.f = attempt.f1;
            h = h_new;

            if landing {
                if t_new >= self.t_end {
                    return self.finish(Status::Success, "");
                }
                // A time stop: let the system switch regime, then restart f.
                self.stops.remove(0);
                self.stats.time_stops += 1;
                let action = self.sys.on_time_stop(t_new, &mut y_new, &mut ctl);
                self.y = y_new;
                self.take_new_stops(&mut ctl);
                if action == EventAction::Stop || ctl.stop_requested {
                    return self.finish(Status::StoppedByEvent, "");
                }
                if !self.restart_at(t_new, &y_new) {
                    return self.finish(
                        Status::NonFinite,
                        format!("f is not finite at the time stop t = {t_new}"),
                    );
                }
            }
        }
    }

    /// After a handler (event or time stop) at `(t, y)`: evaluate `f` and the event functions
    /// anew there. Returns false if `f` is not finite.
    fn restart_at(&mut self, t: f64, y: &State<N>) -> bool {
        self.f = self.rhs(t, y);
        let mut g = [0.0; MAX_EVENTS];
        self.eval_events(t, y, &mut g);
        self.g = g;
        self.f.iter().all(|v| v.is_finite())
    }

    /// Hairer's initial step selection from the current state (one evaluation).
    fn select_step(&mut self, order: u32, h_max: f64) -> f64 {
        let (t, y, f) = (self.t, self.y, self.f);
        let w = self.weights;
        let sys = &*self.sys;
        let mut evals = 0;
        let h = initial_step(
            &y,
            &f,
            order,
            h_max,
            |v, yy| w.scaled_sq(v, yy),
            |h, y1| {
                evals += 1;
                sys.rhs(t + h, y1)
            },
        );
        self.stats.rhs_evals += evals;
        h
    }

    /// Whether the step provably holds no crossing of any event function: each has one strict
    /// sign at both ends (`self.g` at `t0`, `g1` at `t1`) and the system's bound of its
    /// straying from the chord ([`OdeSystem::event_chord_bounds`], all functions at once) is
    /// below its smaller end value, so it cannot reach zero inside.
    fn holds_no_crossing(&self, dense: &DenseOutput<N>, t0: f64, t1: f64, g1: &[f64]) -> bool {
        let deviation = dense.chord_deviation();
        let mut bounds = [f64::NAN; MAX_EVENTS];
        let n = self.n_events;
        self.sys
            .event_chord_bounds(t0, t1, &deviation, &mut bounds[..n]);
        (0..n).all(|i| {
            let (a, b) = (self.g[i], g1[i]);
            let margin = if a > 0.0 && b > 0.0 {
                a.min(b)
            } else if a < 0.0 && b < 0.0 {
                -a.max(b)
            } else {
                return false;
            };
            // NaN (no bound) fails the test
            bounds[i] < margin
        })
    }

    /// Find and handle the events in `(t0, t1]`, in time order. Returns where the step ends if
    /// a handler cut it (`Restart` or `Stop`), the state there (after the handler), and the
    /// strongest action taken. `self.g` holds the values at `t0` on entry and at the end of
    /// what was scanned on return.
    fn scan_events(
        &mut self,
        dense: &DenseOutput<N>,
        t0: f64,
        t1: f64,
        y1: &State<N>,
        ctl: &mut Control,
    ) -> (f64, State<N>, EventAction) {
        let n = self.n_events;
        if n == 0 {
            return (t1, *y1, EventAction::Continue);
        }
        let mut g_end = [0.0; MAX_EVENTS];
        self.eval_events(t1, y1, &mut g_end);
        if self.holds_no_crossing(dense, t0, t1, &g_end) {
            self.g = g_end;
            return (t1, *y1, EventAction::Continue);
        }
        let segments = self.opts.event_subdivisions + 1;
        let fraction = |k: usize| match self.scan_fractions.get(k - 1) {
            Some(&q) => q,
            None => k as f64 / segments as f64,
        };
        // The directions, asked once per step: they change only when a handler runs, and the
        // scan asks again after every handler (below).
        let mut dirs = [Direction::Both; MAX_EVENTS];
        for (i, d) in dirs[..n].iter_mut().enumerate() {
            *d = self.sys.event_direction(i);
        }
        let mut lo_t = t0;
        let mut g_lo = self.g;
        let mut k = 1;
        while k <= segments {
            let hi_t = if k == segments {
                t1
            } else {
                t0 + (t1 - t0) * fraction(k)
            };
            if hi_t <= lo_t {
                k += 1;
                continue;
            }
            let mut g_hi = g_end;
            if hi_t != t1 {
                self.eval_events(hi_t, &dense.eval(hi_t), &mut g_hi);
            }

            // Locate every crossing in (lo_t, hi_t]; keep the earliest time.
            let mut t_first = f64::INFINITY;
            let mut times = [f64::INFINITY; MAX_EVENTS];
            for i in 0..n {
                if dirs[i].crosses(g_lo[i], g_hi[i]) {
                    let sys = &*self.sys;
                    let te = locate(
                        |tt| sys.event(i, tt, &dense.eval(tt)),
                        lo_t,
                        g_lo[i],
                        hi_t,
                        g_hi[i],
                    );
                    times[i] = te;
                    t_first = t_first.min(te);
                }
            }
            if t_first.is_infinite() {
                lo_t = hi_t;
                g_lo = g_hi;
                k += 1;
                continue;
            }
            // Handle every event at that instant, in index order.
            let y_state = if t_first == t1 {
                *y1
            } else {
                dense.eval(t_first)
            };
            let mut y_after = y_state;
            let mut strongest = EventAction::Continue;
            for i in 0..n {
                if times[i] != t_first {
                    continue;
                }
                self.stats.events += 1;
                self.events.push(EventRecord {
                    t: t_first,
                    index: i,
                    rising: g_lo[i] < 0.0,
                    state: y_state,
                });
                let action = self.sys.on_event(i, t_first, &mut y_after, ctl);
                strongest = match (strongest, action) {
                    (EventAction::Stop, _) | (_, EventAction::Stop) => EventAction::Stop,
                    (EventAction::Restart, _) | (_, EventAction::Restart) => EventAction::Restart,
                    _ => EventAction::Continue,
                };
            }
            if strongest != EventAction::Continue {
                return (t_first, y_after, strongest);
            }
            for (i, d) in dirs[..n].iter_mut().enumerate() {
                *d = self.sys.event_direction(i);
            }
            // Record-only: go on scanning from the far side of the crossing, with the values
            // the handlers may have changed.
            self.eval_events(t1, y1, &mut g_end);
            lo_t = t_first;
            let mut g = [0.0; MAX_EVENTS];
            self.eval_events(t_first, &y_state, &mut g);
            g_lo = g;
        }
        self.g = g_lo;
        (t1, *y1, EventAction::Continue)
    }
}
