//! Where the next step ends: the controller's size, shortened to end just past a forecast
//! crossing of an event function or on a forecast kink, and landing exactly on the next time
//! stop or the end; and the first step after a restart.
//!
//! The plan's parts, each in its own file: the events' forecast (`crossing_forecast.rs`, read
//! through [`crate::events::EventScan::next_crossing`]), the kinks' ([`KinkForecast`]), and the
//! first step learned after a recurring event ([`RestartSteps`]).

use crate::dense::DenseOutput;
use crate::kinks::KinkForecast;
use crate::options::SolverOptions;
use crate::restart_steps::RestartSteps;
use crate::stepper::Stepper;
use crate::system::{Control, OdeSystem};
use crate::State;

/// How far past a forecast crossing a step aims, as a share of the way there: far enough that
/// a forecast a little early still puts the crossing inside the step (the quadratic's error
/// shrinks like the cube of the step), near enough that the step runs only a sliver into the
/// new regime. A step taken again for a kinked crossing it found inside (`step_guard.rs`) ends
/// as far past it.
pub(crate) const LAND_PAST: f64 = 0.01;

/// At most this many steps in a row are shortened to a forecast crossing; then one step of the
/// controller's own size. A function that closes on zero without crossing it would otherwise
/// draw the steps ever shorter (`tests::at_most_three_steps_in_a_row_are_shortened`).
const MAX_FORECAST_STEPS: u32 = 3;

/// A step landing on a time stop (or the end) when it would otherwise end within this factor
/// of its size before it: stretched a little rather than leaving a sliver.
const STRETCH: f64 = 1.01;

/// What the plan asks of the method, constants of it read through the [`Stepper`] trait (and
/// folded away in the loop built for the method).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stepping {
    /// The method controls its step ([`Stepper::is_adaptive`]); else every step is the
    /// settings' `fixed_step`.
    pub(crate) adaptive: bool,
    /// Its steps end on forecast kinks ([`Stepper::lands_on_kinks`]).
    pub(crate) lands_on_kinks: bool,
}

impl Stepping {
    #[inline(always)]
    pub(crate) fn of<M: Stepper<N>, const N: usize>(method: &M) -> Self {
        Stepping {
            adaptive: method.is_adaptive(),
            lands_on_kinks: method.lands_on_kinks(),
        }
    }
}

/// One step as planned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Planned {
    /// The step's size.
    pub(crate) h: f64,
    /// The controller's size for it, before a forecast or a stop cut it: the steps after are
    /// planned from it.
    pub(crate) h_ctrl: f64,
    /// Shortened to a forecast crossing or kink.
    forecast_limited: bool,
    /// Lands on the next time stop or the end, `next_stop`.
    pub(crate) landing: bool,
    next_stop: f64,
}

impl Planned {
    /// Where the step from `t` ends: on the stop itself when it lands there (`t + h` may round
    /// to either side of it).
    #[inline]
    pub(crate) fn end(&self, t: f64) -> f64 {
        if self.landing {
            self.next_stop
        } else {
            t + self.h
        }
    }
}

/// The step plan's state across a run.
pub(crate) struct StepPlan {
    t_end: f64,
    /// The largest step: the settings' `h_max`, at most the run's length.
    h_max: f64,
    /// Every step of a method that does not control its step.
    fixed_step: f64,
    /// Pending time stops, ascending, all after the current time.
    stops: Vec<f64>,
    /// The next forecast kink, for a method that lands on them (`kinks.rs`).
    kinks: KinkForecast,
    /// Steps in a row shortened to a forecast crossing ([`MAX_FORECAST_STEPS`]).
    limited_streak: u32,
    /// The first step accepted after each event that restarted the run (`restart_steps.rs`).
    restart_steps: RestartSteps,
}

impl StepPlan {
    /// For a run from `t0` to `t_end` under `opts`.
    pub(crate) fn new(t0: f64, t_end: f64, opts: &SolverOptions) -> Self {
        let mut stops: Vec<f64> = (opts.time_stops.iter().copied())
            .filter(|&s| s > t0 && s < t_end)
            .collect();
        stops.sort_by(|a, b| a.total_cmp(b));
        stops.dedup();
        // handlers' stops join them without allocating in the loop, up to this many
        stops.reserve(16);
        StepPlan {
            t_end,
            h_max: opts.h_max.min(t_end - t0),
            fixed_step: opts.fixed_step,
            stops,
            kinks: KinkForecast::new(0),
            limited_streak: 0,
            restart_steps: RestartSteps::new(),
        }
    }

    /// The largest step.
    #[inline]
    pub(crate) fn h_max(&self) -> f64 {
        self.h_max
    }

    /// Whether `t` is the run's end.
    #[inline]
    pub(crate) fn at_end(&self, t: f64) -> bool {
        t >= self.t_end
    }

    /// Follow the system's `n` kink functions from `(t, y)`, to land on their crossings.
    pub(crate) fn follow_kinks<S: OdeSystem<N>, const N: usize>(
        &mut self,
        n: usize,
        sys: &S,
        t: f64,
        y: &State<N>,
    ) {
        self.kinks = KinkForecast::new(n);
        self.kinks.reset(sys, t, y);
    }

    /// The next step from `t` by the method `m`, given the controller's size `h`, the events'
    /// forecast crossing `next_crossing` and whether a forecast may shorten the step
    /// (`forecast`). `Err` with the step's size if it is too small to take at `t`.
    #[inline]
    pub(crate) fn next(
        &self,
        t: f64,
        h: f64,
        next_crossing: f64,
        forecast: bool,
        m: Stepping,
    ) -> Result<Planned, f64> {
        let next_stop = self
            .stops
            .first()
            .copied()
            .unwrap_or(self.t_end)
            .min(self.t_end);
        let mut h = if m.adaptive {
            h.min(self.h_max)
        } else {
            self.fixed_step
        };
        let h_ctrl = h;
        let mut forecast_limited = false;
        if m.adaptive && self.limited_streak < MAX_FORECAST_STEPS && forecast {
            // End the step where an event function closing on zero is forecast to cross it
            // rather than run past it into the new regime (`crossing_forecast.rs`).
            let to_crossing = (next_crossing - t) * (1.0 + LAND_PAST);
            if to_crossing < h && to_crossing > 1e3 * f64::EPSILON * t.abs() {
                h = to_crossing;
                forecast_limited = true;
            }
            if m.lands_on_kinks {
                if let Some(to_kink) = self.kinks.landing(t, h) {
                    h = to_kink;
                    forecast_limited = true;
                }
            }
        }
        let landing = t + STRETCH * h >= next_stop;
        if landing {
            h = next_stop - t;
        }
        if 0.1 * h.abs() <= t.abs() * f64::EPSILON || h <= 0.0 {
            return Err(h);
        }
        Ok(Planned {
            h,
            h_ctrl,
            forecast_limited,
            landing,
            next_stop,
        })
    }

    /// The step `step` was accepted and the controller proposes `h_new`: the size to plan the
    /// next step from. A step shortened by a forecast does not shrink the ones after it.
    #[inline]
    pub(crate) fn accepted(&mut self, step: &Planned, h_new: f64) -> f64 {
        if step.forecast_limited {
            self.limited_streak += 1;
            h_new.max(step.h_ctrl)
        } else {
            self.limited_streak = 0;
            h_new
        }
    }

    /// The run keeps a step from `t0` to `t1` (not cut by an event), ending at `y1`: forecast
    /// the next kink.
    #[inline]
    pub(crate) fn after_step<S: OdeSystem<N>, const N: usize>(
        &mut self,
        sys: &S,
        dense: &DenseOutput<N>,
        (t0, t1): (f64, f64),
        y1: &State<N>,
    ) {
        self.kinks.after_step(sys, dense, (t0, t1), y1);
    }

    /// The time stops a handler asked for at `t` join the plan.
    #[inline]
    pub(crate) fn add_stops(&mut self, t: f64, ctl: &mut Control) {
        for s in ctl.new_time_stops.drain(..) {
            if s > t && s < self.t_end && s.is_finite() && !self.stops.contains(&s) {
                let pos = self.stops.partition_point(|&x| x < s);
                self.stops.insert(pos, s);
            }
        }
    }

    /// The step landed on the next time stop.
    pub(crate) fn pass_stop(&mut self) {
        self.stops.remove(0);
    }

    /// A restart at `(t, y)` (a handler changed the state or the regime): no kink forecast.
    #[inline]
    pub(crate) fn restart_kinks<S: OdeSystem<N>, const N: usize>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
    ) {
        self.kinks.reset(sys, t, y);
    }

    /// A restart after the event `event` (index, rising): the first step learned after it the
    /// last time, at most `h_max` (`restart_steps.rs`).
    #[inline]
    pub(crate) fn restart(&mut self, event: Option<(usize, bool)>) -> Option<f64> {
        (self.restart_steps.restart(event)).map(|h| h.min(self.h_max))
    }

    /// An attempt of size `h` was rejected, or accepted and taken back.
    #[inline]
    pub(crate) fn rejected(&mut self, h: f64) {
        self.restart_steps.rejected(h);
    }

    /// The run kept `kept` of a step accepted with the scaled error `err` by a method of order
    /// `order`: only now may it teach a restart its first step, and only the part of it the
    /// run keeps (`restart_steps.rs`; `cushion-model/tests/model/recurring_events.rs`).
    #[inline]
    pub(crate) fn kept(&mut self, kept: f64, err: Option<f64>, order: u32) {
        self.restart_steps.accepted(kept, err, order);
    }

    /// The method changed (`auto`): the first steps learned belong to the method that took
    /// them.
    pub(crate) fn forget_restart_steps(&mut self) {
        self.restart_steps = RestartSteps::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ADAPTIVE: Stepping = Stepping {
        adaptive: true,
        lands_on_kinks: false,
    };

    fn plan(stops: &[f64]) -> StepPlan {
        let opts = SolverOptions {
            time_stops: stops.to_vec(),
            ..SolverOptions::default()
        };
        StepPlan::new(0.0, 10.0, &opts)
    }

    #[test]
    fn a_step_lands_on_the_next_stop_and_the_stops_are_ordered() {
        let mut p = plan(&[5.0, 2.0, 2.0, -1.0, 12.0]);
        assert_eq!(p.stops, [2.0, 5.0]);
        // 1 + 1.01 * 0.995 passes 2: stretched onto it
        let step = p.next(1.0, 0.995, f64::INFINITY, true, ADAPTIVE).unwrap();
        assert!(step.landing && step.end(1.0) == 2.0 && step.h == 1.0);
        assert_eq!(step.h_ctrl, 0.995);
        // well short of it: not landing
        let step = p.next(1.0, 0.5, f64::INFINITY, true, ADAPTIVE).unwrap();
        assert!(!step.landing && step.end(1.0) == 1.5);
        p.pass_stop();
        let mut ctl = Control::new();
        for s in [4.0, 5.0, 3.0, 1.0, 11.0, f64::NAN] {
            ctl.add_time_stop(s);
        }
        p.add_stops(2.0, &mut ctl);
        assert_eq!(p.stops, [3.0, 4.0, 5.0]);
        assert!(ctl.new_time_stops.is_empty());
        // the end is a stop too
        p.stops.clear();
        let step = p.next(9.5, 1.0, f64::INFINITY, true, ADAPTIVE).unwrap();
        assert!(step.landing && step.end(9.5) == 10.0 && p.at_end(step.end(9.5)));
    }

    #[test]
    fn a_forecast_crossing_ends_the_step_just_past_it_and_the_next_step_grows_back() {
        let mut p = plan(&[]);
        let step = p.next(1.0, 0.5, 1.2, true, ADAPTIVE).unwrap();
        assert_eq!(step.h, (1.2 - 1.0) * (1.0 + LAND_PAST));
        // the controller's size is kept for the step after
        assert_eq!(p.accepted(&step, 0.3), 0.5);
        // not when a forecast may not shorten the step (`StepGuard::allows_forecast`)
        assert_eq!(p.next(1.0, 0.5, 1.2, false, ADAPTIVE).unwrap().h, 0.5);
        // nor a crossing beyond the step
        assert_eq!(p.next(1.0, 0.1, 1.2, true, ADAPTIVE).unwrap().h, 0.1);
    }

    #[test]
    fn at_most_three_steps_in_a_row_are_shortened() {
        let mut p = plan(&[]);
        for _ in 0..MAX_FORECAST_STEPS {
            let step = p.next(1.0, 0.5, 1.2, true, ADAPTIVE).unwrap();
            assert!(step.h < 0.5);
            p.accepted(&step, 0.5);
        }
        // one step of the controller's own size, then forecasts again
        let step = p.next(1.0, 0.5, 1.2, true, ADAPTIVE).unwrap();
        assert_eq!(step.h, 0.5);
        p.accepted(&step, 0.5);
        assert!(p.next(1.0, 0.5, 1.2, true, ADAPTIVE).unwrap().h < 0.5);
    }

    #[test]
    fn a_fixed_step_is_not_shortened_by_a_forecast() {
        let opts = SolverOptions {
            fixed_step: 0.25,
            ..SolverOptions::default()
        };
        let p = StepPlan::new(0.0, 10.0, &opts);
        let fixed = Stepping {
            adaptive: false,
            lands_on_kinks: false,
        };
        let step = p.next(1.0, 3.0, 1.1, true, fixed).unwrap();
        assert_eq!(step.h, 0.25);
    }

    #[test]
    fn a_step_too_small_for_the_time_is_refused() {
        let p = plan(&[]);
        assert!(p.next(1.0, 1e-17, f64::INFINITY, true, ADAPTIVE).is_err());
        assert!(p.next(1.0, 1e-12, f64::INFINITY, true, ADAPTIVE).is_ok());
    }

    #[test]
    fn a_learned_first_step_is_at_most_the_largest_step() {
        let opts = SolverOptions {
            h_max: 1e-6,
            ..SolverOptions::default()
        };
        let mut p = StepPlan::new(0.0, 10.0, &opts);
        let event = Some((0, true));
        assert_eq!(p.restart(event), None);
        p.kept(1e-6, Some(1e-10), 5);
        assert_eq!(p.restart(event), Some(1e-6));
    }
}
