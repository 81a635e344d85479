//! Events: detection, location and dispatch within one accepted step.
//!
//! Detection compares the signs of the event functions at the step's ends and at interior
//! points of the dense output (`SolverOptions::event_subdivisions`), so two crossings inside one
//! step are both found; a step that provably holds no crossing (the system's chord bounds,
//! [`OdeSystem::event_chord_bounds`]) is not sampled inside, and in a step that may hold one
//! only the functions the bounds do not clear are (all of them again once a handler has acted:
//! `tests/integrator/events.rs::a_function_a_handler_changes_inside_the_step_is_scanned_again`).
//! Location (`event_locate.rs`) is a bracketing root finder (regula falsi with Anderson and
//! Björck's weights, safeguarded by bisection) on the dense output ([`locate`]); a crossing
//! and back between two scan points is found at the function's extremum (`event_dip.rs`).
//! Dispatch calls the system's handlers in time order, and at one instant in index order.
//!
//! The loop sees [`EventScan`] through [`EventScan::reset`] (after a restart),
//! [`EventScan::scan`] (one accepted step), [`EventScan::take_redo`] (a crossing that asks for
//! the step again), [`EventScan::next_crossing`] (the forecast, `crossing_forecast.rs`) and the
//! log.
//!
//! A function exactly zero where a step starts has no side, and a crossing needs a start
//! strictly on one side ([`Direction::crosses`]). Where a handler has just acted (and at the
//! start of a run), such a function is given the side it takes a moment later: it is evaluated
//! at `t + delta` along the solution, `delta = 100 eps (|t| + span)` (`span` the run's length),
//! as SUNDIALS' CVODE does after a root, where it checks `g` at `t + 100 uround (|t| + |h|)`.
//! A contact that begins at penetration zero is then in contact, not at its edge, and one that
//! ends and touches again at once is found; a function still zero there (at rest on its
//! threshold) fires only once it has left zero. Guarded by
//! `tests/integrator/events.rs::a_function_zero_where_a_handler_left_it_takes_the_side_it_moves_to`.
//!
//! Kinked crossings. Where `f` itself loses smoothness at a crossing
//! ([`OdeSystem::kinked_at_event`]: a Hertz force `k delta^1.5` vanishing as its contact
//! ends), the state there, read from the dense output of a step that ran past it, carries the
//! error of a step across a kink, which an embedded estimate built for smooth solutions does not
//! see. DOP853's two estimates give 0.22 and 0.04 of the true error for a `delta^1.5` that
//! vanishes in the middle of a step, but 2.3 and 1.07 for one that vanishes at 0.99 of it
//! (`lab/dop853_onset.py`). So, for a method that asks ([`crate::stepper::Stepper::lands_on_kinks`]),
//! a step whose first crossing is such a kink, found between [`REDO_AFTER`] and
//! [`REDO_BEFORE`] of its length, is not handled: the scan reports the crossing and the loop
//! takes the step again, once, ending just past it (`step_guard.rs`). The crossing is then found
//! at the end of the new step and handled there. Guarded by
//! `tests/integrator/stiff_contact.rs::a_lift_off_inside_a_step_is_taken_again`.
//!
//! Crossings on a dense output that is not stable. Where a step is held by stability (DOP853
//! past its continuous extension's boundary, `Stepper::dense_stability_boundary`), or passed
//! its error test far past it because the stiff mode was at rest, the states its dense output
//! gives inside the step are amplified rounding, not the solution: a crossing found there may
//! not exist, and its time and state are not to be trusted. The loop asks the scan to report
//! every crossing of such a step instead of handling it, and takes the step again short enough
//! for its dense output to be stable (`step_guard.rs`). Guarded by
//! `cushion-model/tests/model/dop853_at_rest.rs`.

use crate::dense::DenseOutput;
use crate::event_dip as dip;
pub use crate::event_locate::locate;
use crate::options::SolverOptions;
use crate::solution::{EventRecord, Stats};
use crate::system::{Control, Direction, EventAction, OdeSystem, MAX_EVENTS};
use crate::State;

/// A kinked crossing found before this share of a step asks for the step again. From 0.93 of
/// the step on, both of DOP853's estimates are at or above the true error of a `delta^1.5`
/// that vanishes there (1.07 to 48 times; at 0.90 the combined one is 0.27 of it:
/// `python3 lab/dop853_onset.py 0.01 0.9 0.93 0.95 0.97 0.99`), so the step is judged
/// as it is.
pub const REDO_BEFORE: f64 = 0.95;

/// A kinked crossing within this share of a step's start is kept: there it costs the step
/// little (at 0.01 the true error is 0.03 of that at the middle, though the estimates see only
/// 0.15 and 0.26 of it), and the step taken again would be a sliver.
pub const REDO_AFTER: f64 = 0.01;

/// How far from zero a function with the values `a` and `b` at an interval's ends stays at
/// them, the smaller of `|a|` and `|b|`, if both are strictly on one side; `None` otherwise.
fn clearance(a: f64, b: f64) -> Option<f64> {
    let same_side = (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0);
    same_side.then(|| a.abs().min(b.abs()))
}

/// Whether a function with the values `a` and `b` (one strict sign) at a segment's ends may
/// cross zero and come back inside it: its straying from the chord may reach zero (`bound`,
/// the step's chord bound; NaN, no bound: the samples alone decide).
fn may_dip(a: f64, b: f64, bound: f64) -> bool {
    clearance(a, b).is_some_and(|c| bound >= c)
}

/// Interior scan fractions computed in advance; more subdivisions than this (unusual) are
/// divided on the fly.
const MAX_PRECOMPUTED_FRACTIONS: usize = 64;

/// Which functions a step's scan searches, and how: those the system's chord bound does not
/// clear (all, once a handler has acted), their directions, and the bounds (for the dip test).
struct Searched {
    open: [bool; MAX_EVENTS],
    all_open: bool,
    dirs: [Direction; MAX_EVENTS],
    bounds: [f64; MAX_EVENTS],
}

/// The event functions' state across a run: their values at the current time, the scan
/// points, and the log of every event handled.
pub struct EventScan<const N: usize> {
    n: usize,
    /// `g_i` at the current time (the start of the next step).
    g: [f64; MAX_EVENTS],
    /// Interior points per step plus one.
    segments: usize,
    /// `k / segments` for the first interior points `k = 1, 2, ...`, divided once here rather
    /// than every step (the same numbers).
    scan_fractions: Vec<f64>,
    /// Every event handled, in time order.
    pub log: Vec<EventRecord<N>>,
    /// `100 eps span`: with `100 eps |t|`, how far past a point a zero function is looked at.
    look_past: f64,
    /// Where an event function closing on zero is forecast to cross it after the current time
    /// ([`crate::crossing_forecast`]); infinite when none is within reach of the next step.
    next_crossing: f64,
    /// A kinked crossing the last scan found well inside its step, not handled: the step is
    /// to be taken again ([`EventScan::take_redo`]).
    redo_at: Option<f64>,
}

impl<const N: usize> EventScan<N> {
    /// For `n_events` functions over a run of length `span` (s).
    pub fn new(n_events: usize, opts: &SolverOptions, span: f64) -> Self {
        let segments = opts.event_subdivisions.saturating_add(1);
        let scan_fractions = if n_events == 0 {
            Vec::new()
        } else {
            (1..segments.min(MAX_PRECOMPUTED_FRACTIONS + 1))
                .map(|k| k as f64 / segments as f64)
                .collect()
        };
        EventScan {
            n: n_events.min(MAX_EVENTS),
            g: [0.0; MAX_EVENTS],
            segments,
            scan_fractions,
            log: Vec::with_capacity(64),
            look_past: 100.0 * f64::EPSILON * span.abs(),
            next_crossing: f64::INFINITY,
            redo_at: None,
        }
    }

    /// Where an event function closing on zero is forecast to cross it, after the step that
    /// ended last (infinite: none forecast).
    pub fn next_crossing(&self) -> f64 {
        self.next_crossing
    }

    /// Where the kinked crossing is that the last scan left unhandled, asking for its step to
    /// be taken again (module doc, "Kinked crossings"); `None` if it handled the step.
    pub fn take_redo(&mut self) -> Option<f64> {
        self.redo_at.take()
    }

    /// Forecast the next crossing after a step from `t0` to `t1` that crossed nothing: of
    /// each function with one strict sign at both ends, closing on zero, that would fire
    /// there and whose chord reaches zero within `FORECAST_REACH` steps, the first zero of
    /// the quadratic through its values at the ends and the middle.
    fn forecast<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        dense: &DenseOutput<N>,
        (t0, t1): (f64, f64),
        g1: &[f64; MAX_EVENTS],
    ) {
        let span = t1 - t0;
        let t_mid = t0 + 0.5 * span;
        let mut y_mid = None;
        let mut next = f64::INFINITY;
        for (i, (&a, &b)) in self.g[..self.n].iter().zip(g1).enumerate() {
            if !crate::crossing_forecast::closes_within_reach(a, b) {
                continue;
            }
            if !sys.event_direction(i).crosses(b, -b) {
                continue;
            }
            let y = *y_mid.get_or_insert_with(|| dense.eval(t_mid));
            let g_mid = sys.event(i, t_mid, &y);
            if let Some(tau) = crate::crossing_forecast::zero_after(span, a, g_mid, b) {
                next = next.min(t1 + tau);
            }
        }
        self.next_crossing = next;
    }

    /// Give each function of `g` that is exactly zero at `t` the value it takes at
    /// `t + delta` (see the module's doc), the state there from `state_at`.
    fn side_of_zeros<S: OdeSystem<N>>(
        &self,
        sys: &S,
        t: f64,
        g: &mut [f64; MAX_EVENTS],
        state_at: impl Fn(f64) -> State<N>,
    ) {
        if !g[..self.n].contains(&0.0) {
            return;
        }
        let t_past = t + 100.0 * f64::EPSILON * t.abs() + self.look_past;
        let y_past = state_at(t_past);
        for (i, gi) in g[..self.n].iter_mut().enumerate() {
            if *gi == 0.0 {
                *gi = sys.event(i, t_past, &y_past);
            }
        }
    }

    fn eval<S: OdeSystem<N>>(&self, sys: &S, t: f64, y: &State<N>, g: &mut [f64; MAX_EVENTS]) {
        if self.n > 0 {
            sys.events(t, y, &mut g[..self.n]);
        }
    }

    /// Evaluate the event functions at `(t, y)`, where `f = f(t, y)`: the start of the run,
    /// or after a handler changed the state or the regime. A function exactly zero there
    /// takes the side it moves to (along `y + (tau - t) f`).
    pub fn reset<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: &State<N>, f: &State<N>) {
        let mut g = [0.0; MAX_EVENTS];
        self.eval(sys, t, y, &mut g);
        self.side_of_zeros(sys, t, &mut g, |tau| y + f * (tau - t));
        self.g = g;
        self.next_crossing = f64::INFINITY;
    }

    /// Whether the step provably holds no crossing of any event function: each has one strict
    /// sign at both ends (`self.g` at `t0`, `g1` at `t1`) and the system's bound of its
    /// straying from the chord ([`OdeSystem::event_chord_bounds`], all functions at once,
    /// written into `bounds` for the scan's dip test) is below its smaller end value, so it
    /// cannot reach zero inside.
    fn holds_no_crossing<S: OdeSystem<N>>(
        &self,
        sys: &S,
        dense: &DenseOutput<N>,
        t0: f64,
        t1: f64,
        g1: &[f64],
        bounds: &mut [f64; MAX_EVENTS],
    ) -> bool {
        let deviation = dense.chord_deviation();
        let n = self.n;
        sys.event_chord_bounds(t0, t1, &deviation, &mut bounds[..n]);
        // NaN (no bound) fails the test
        (0..n).all(|i| clearance(self.g[i], g1[i]).is_some_and(|c| bounds[i] < c))
    }

    /// Find and handle the events in `(t0, t1]`, in time order. Returns where the step ends if
    /// a handler cut it (`Restart` or `Stop`), the state there (after the handler), and the
    /// strongest action taken. `self.g` holds the values at `t0` on entry and at the end of
    /// what was scanned on return.
    ///
    /// With `redo_kinked`, a first crossing that is a kink of `f`, between [`REDO_AFTER`] and
    /// [`REDO_BEFORE`] of the step, is neither handled nor logged: the scan returns `Continue`
    /// at `t1` with `self.g` as on entry, and [`EventScan::take_redo`] gives the crossing. With
    /// `redo_any` (the step's dense output is not stable: module doc), so is any first crossing.
    #[allow(clippy::too_many_arguments)]
    pub fn scan<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        dense: &DenseOutput<N>,
        (t0, t1): (f64, f64),
        y1: &State<N>,
        ctl: &mut Control,
        stats: &mut Stats,
        redo_kinked: bool,
        redo_any: bool,
    ) -> (f64, State<N>, EventAction) {
        let n = self.n;
        if n == 0 {
            return (t1, *y1, EventAction::Continue);
        }
        let mut g_end = [0.0; MAX_EVENTS];
        self.eval(&*sys, t1, y1, &mut g_end);
        let mut bounds = [f64::NAN; MAX_EVENTS];
        if self.holds_no_crossing(&*sys, dense, t0, t1, &g_end, &mut bounds) {
            self.forecast(&*sys, dense, (t0, t1), &g_end);
            self.g = g_end;
            return (t1, *y1, EventAction::Continue);
        }
        // The functions the bound clears cannot cross inside the step: only the others are
        // sampled at the interior points and searched, until a handler acts (then all are).
        let mut open = [true; MAX_EVENTS];
        for (i, o) in open[..n].iter_mut().enumerate() {
            *o = !clearance(self.g[i], g_end[i]).is_some_and(|c| bounds[i] < c);
        }
        let all_open = open[..n].iter().all(|&o| o);
        let segments = self.segments;
        // The directions, asked once per step: they change only when a handler runs, and the
        // scan asks again after every handler (below).
        let mut dirs = [Direction::Both; MAX_EVENTS];
        for (i, d) in dirs[..n].iter_mut().enumerate() {
            *d = sys.event_direction(i);
        }
        let mut searched = Searched {
            open,
            all_open,
            dirs,
            bounds,
        };
        let mut lo_t = t0;
        let mut g_lo = self.g;
        // whether a crossing of this step was handled: one after it is not taken again, since
        // the handlers have acted
        let mut handled = false;
        let mut k = 1;
        while k <= segments {
            let hi_t = if k == segments {
                t1
            } else {
                t0 + (t1 - t0) * self.fraction(k)
            };
            if hi_t <= lo_t {
                k += 1;
                continue;
            }
            let mut g_hi = g_end;
            self.values_at(&*sys, dense, &searched, (hi_t, t1), &mut g_hi);

            let mut times = [f64::INFINITY; MAX_EVENTS];
            let segment = (lo_t, hi_t);
            let t_first =
                self.crossings(&*sys, dense, &searched, segment, (&g_lo, &g_hi), &mut times);
            if t_first.is_infinite() {
                lo_t = hi_t;
                g_lo = g_hi;
                k += 1;
                continue;
            }
            let kinked = redo_kinked
                && t_first > t0 + REDO_AFTER * (t1 - t0)
                && t_first < t0 + REDO_BEFORE * (t1 - t0)
                && (0..n).any(|i| times[i] == t_first && sys.kinked_at_event(i));
            if !handled && (redo_any || kinked) {
                self.redo_at = Some(t_first);
                return (t1, *y1, EventAction::Continue);
            }
            handled = true;
            let y_state = if t_first == t1 {
                *y1
            } else {
                dense.eval(t_first)
            };
            let (strongest, y_after) =
                self.handle(sys, (t_first, &y_state), t1, (&times, &g_lo), ctl, stats);
            if strongest != EventAction::Continue {
                return (t_first, y_after, strongest);
            }
            for (i, d) in searched.dirs[..n].iter_mut().enumerate() {
                *d = sys.event_direction(i);
            }
            // a handler may have changed the functions the bound cleared
            searched.open = [true; MAX_EVENTS];
            searched.all_open = true;
            // Record-only: go on scanning from the far side of the crossing, with the values
            // the handlers may have changed.
            self.eval(&*sys, t1, y1, &mut g_end);
            lo_t = t_first;
            let mut g = [0.0; MAX_EVENTS];
            self.eval(&*sys, t_first, &y_state, &mut g);
            self.side_of_zeros(&*sys, t_first, &mut g, |tau| dense.eval(tau));
            g_lo = g;
        }
        if lo_t == t0 {
            self.forecast(&*sys, dense, (t0, t1), &g_lo);
        } else {
            // a crossing was recorded inside the step: the values at its start no longer
            // describe one smooth approach
            self.next_crossing = f64::INFINITY;
        }
        self.g = g_lo;
        (t1, *y1, EventAction::Continue)
    }

    /// `k / segments`, the share of a step at its `k`-th interior scan point.
    #[inline(always)]
    fn fraction(&self, k: usize) -> f64 {
        match self.scan_fractions.get(k - 1) {
            Some(&q) => q,
            None => k as f64 / self.segments as f64,
        }
    }

    /// The values at `hi_t` of the functions `s` searches, on the dense output of a step that
    /// ends at `t1`, written into `g_hi` (which holds the values at `t1`); a cleared function
    /// keeps its value at `t1` (the same side, never searched).
    #[inline(always)]
    fn values_at<S: OdeSystem<N>>(
        &self,
        sys: &S,
        dense: &DenseOutput<N>,
        s: &Searched,
        (hi_t, t1): (f64, f64),
        g_hi: &mut [f64; MAX_EVENTS],
    ) {
        if hi_t != t1 {
            let y_hi = dense.eval(hi_t);
            if s.all_open {
                self.eval(sys, hi_t, &y_hi, g_hi);
            } else {
                for i in (0..self.n).filter(|&i| s.open[i]) {
                    g_hi[i] = sys.event(i, hi_t, &y_hi);
                }
            }
        }
    }

    /// Locate the crossing in the segment `(lo_t, hi_t]` of a step of each function `s`
    /// searches, from its values `g_lo` and `g_hi` at the segment's ends: each one's time
    /// written into `times` (left infinite: none); returns the earliest.
    #[inline(always)]
    fn crossings<S: OdeSystem<N>>(
        &self,
        sys: &S,
        dense: &DenseOutput<N>,
        s: &Searched,
        (lo_t, hi_t): (f64, f64),
        (g_lo, g_hi): (&[f64; MAX_EVENTS], &[f64; MAX_EVENTS]),
        times: &mut [f64; MAX_EVENTS],
    ) -> f64 {
        let mut t_first = f64::INFINITY;
        for i in (0..self.n).filter(|&i| s.open[i]) {
            let g = |tt| sys.event(i, tt, &dense.eval(tt));
            let te = if s.dirs[i].crosses(g_lo[i], g_hi[i]) {
                locate(g, lo_t, g_lo[i], hi_t, g_hi[i])
            } else if may_dip(g_lo[i], g_hi[i], s.bounds[i]) && s.dirs[i].crosses(g_lo[i], -g_lo[i])
            {
                // The same side at both ends, but near enough to zero for the output's
                // bend to reach it: a brief crossing and back (a contact that opens and
                // closes again within the segment) is found at the function's extremum.
                match dip::crossing_in_dip(g, lo_t, g_lo[i], hi_t, g_hi[i]) {
                    Some((t_dip, g_dip)) => locate(g, lo_t, g_lo[i], t_dip, g_dip),
                    None => continue,
                }
            } else {
                continue;
            };
            times[i] = te;
            t_first = t_first.min(te);
        }
        t_first
    }

    /// Handle the events at `(t, y)`, in index order: those whose crossing `times` puts there
    /// (`g_lo`: their values before it), each logged, then its handler called. Returns the
    /// strongest action taken and the state after the handlers.
    #[inline(always)]
    fn handle<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        (t, y): (f64, &State<N>),
        t1: f64,
        (times, g_lo): (&[f64; MAX_EVENTS], &[f64; MAX_EVENTS]),
        ctl: &mut Control,
        stats: &mut Stats,
    ) -> (EventAction, State<N>) {
        let mut y_after = *y;
        let mut strongest = EventAction::Continue;
        for i in 0..self.n {
            if times[i] != t {
                continue;
            }
            stats.events += 1;
            self.log.push(EventRecord {
                t,
                index: i,
                rising: g_lo[i] < 0.0,
                state: *y,
            });
            let action = sys.on_event(i, t, &mut y_after, ctl);
            strongest = match (strongest, action) {
                (EventAction::Stop, _) | (_, EventAction::Stop) => EventAction::Stop,
                (EventAction::Restart, _) | (_, EventAction::Restart) => EventAction::Restart,
                _ => EventAction::Continue,
            };
        }
        // A handler that keeps the step may still ask for a time stop inside the rest of
        // it: the step must not run past that stop, so it is cut at the event, as for a
        // restart (`tests/integrator/events.rs::a_time_stop_asked_for_inside_the_step_is_kept`).
        if strongest == EventAction::Continue && ctl.new_time_stops.iter().any(|&s| s > t && s < t1)
        {
            strongest = EventAction::Restart;
        }
        (strongest, y_after)
    }
}
