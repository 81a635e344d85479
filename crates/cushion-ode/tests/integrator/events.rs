//! Event detection, location, actions and time stops.

use cushion_ode::test_models::scheduled_brake::ScheduledBrake;
use cushion_ode::{
    solve, Control, Direction, EventAction, Method, OdeSystem, Output, Solution, SolverOptions,
    State, Status, Tolerance,
};

/// Solve `x' = 1`, `x(0) = 0` over `[0, 1]` with a first step of 1: the solution is linear,
/// so that step is accepted and is the whole run, and every crossing lies inside it.
fn solve_in_one_step<S: OdeSystem<1>>(sys: &mut S) -> Solution<1> {
    let opts = SolverOptions {
        h0: Some(1.0),
        ..Default::default()
    };
    let sol = solve(sys, 0.0, State::<1>::new(0.0), 1.0, &opts);
    assert_eq!(sol.status, Status::Success);
    assert_eq!(sol.stats.steps, 1, "one step over the whole interval");
    sol
}

/// `x' = 1`: `x = t`. Event 0: `(x - a)(x - b)` (both directions), record only.
struct TwoCrossings {
    a: f64,
    b: f64,
}

impl OdeSystem<1> for TwoCrossings {
    fn rhs(&self, _t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(1.0)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<1>, g: &mut [f64]) {
        g[0] = (y[0] - self.a) * (y[0] - self.b);
    }
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        _y: &mut State<1>,
        _ctl: &mut Control,
    ) -> EventAction {
        EventAction::Continue
    }
}

#[test]
fn two_sign_changes_inside_one_step_are_both_found() {
    // The solution is linear: the whole interval is one step, and g has the same sign at both
    // of its ends. Checking only step ends would miss both crossings (SciPy issue 9228).
    let mut sys = TwoCrossings { a: 0.5, b: 0.6 };
    let sol = solve_in_one_step(&mut sys);
    assert_eq!(sol.events.len(), 2);
    assert!((sol.events[0].t - 0.5).abs() < 1e-15);
    assert!(!sol.events[0].rising);
    assert!((sol.events[1].t - 0.6).abs() < 1e-15);
    assert!(sol.events[1].rising);
}

/// `x' = 1`: `x = t`. Event 0: `x - 0.3`, record only; its handler arms event 1, which is the
/// constant 1 until then and `x - 0.6` after. Both have chord bounds (the output's deviation;
/// zero for the constant).
struct Armed {
    armed: bool,
}

impl OdeSystem<1> for Armed {
    fn rhs(&self, _t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(1.0)
    }
    fn event_count(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, y: &State<1>, g: &mut [f64]) {
        g[0] = y[0] - 0.3;
        g[1] = if self.armed { y[0] - 0.6 } else { 1.0 };
    }
    fn event_chord_bound(&self, i: usize, _t0: f64, _t1: f64, dev: &State<1>) -> Option<f64> {
        Some(if i == 1 && !self.armed { 0.0 } else { dev[0] })
    }
    fn on_event(
        &mut self,
        i: usize,
        _t: f64,
        _y: &mut State<1>,
        _ctl: &mut Control,
    ) -> EventAction {
        self.armed |= i == 0;
        EventAction::Continue
    }
}

/// The scan samples inside a step only the functions the chord bound does not clear; a
/// record-only handler that changes the others (here: arms event 1, cleared until then) makes
/// the rest of the step scan them all, so the crossing it causes in the same step is found.
#[test]
fn a_function_a_handler_changes_inside_the_step_is_scanned_again() {
    let mut sys = Armed { armed: false };
    let sol = solve_in_one_step(&mut sys);
    let found: Vec<(usize, f64)> = sol.events.iter().map(|e| (e.index, e.t)).collect();
    assert_eq!(found.len(), 2, "{found:?}");
    assert_eq!(found[0].0, 0);
    assert!((found[0].1 - 0.3).abs() < 1e-15, "{found:?}");
    assert_eq!(found[1].0, 1);
    assert!((found[1].1 - 0.6).abs() < 1e-15, "{found:?}");
}

/// A ball that bounces perfectly elastically, resetting its height to exactly zero, so its
/// event function is exactly zero at every restart.
struct ElasticBall {
    bounces: usize,
}

impl OdeSystem<2> for ElasticBall {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], -1.0)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<2>, g: &mut [f64]) {
        g[0] = y[0];
    }
    fn event_direction(&self, _i: usize) -> Direction {
        Direction::Both
    }
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        y: &mut State<2>,
        _ctl: &mut Control,
    ) -> EventAction {
        self.bounces += 1;
        y[0] = 0.0;
        y[1] = y[1].abs();
        EventAction::Restart
    }
}

#[test]
fn an_event_that_is_zero_at_a_restart_does_not_fire_again() {
    // Drop from x = 0.5 with g = 1: bounces every 2 s after t = 1, the next one 2 s later.
    let mut ball = ElasticBall { bounces: 0 };
    let sol = solve(
        &mut ball,
        0.0,
        State::<2>::new(0.5, 0.0),
        6.5,
        &SolverOptions::default(),
    );
    assert_eq!(sol.status, Status::Success);
    let times: Vec<f64> = sol.events.iter().map(|e| e.t).collect();
    assert_eq!(times.len(), 3, "{times:?}");
    for (t, exact) in times.iter().zip([1.0, 3.0, 5.0]) {
        assert!((t - exact).abs() < 1e-9, "{times:?}");
    }
}

/// `y' = 1` before `t_kink`, then `1 - 3 (t - t_kink)`: continuous with a kink in time (like
/// the robot's velocity profile). Each piece is a polynomial DP5 integrates exactly.
struct Kink {
    t_kink: f64,
}

impl OdeSystem<1> for Kink {
    fn rhs(&self, t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(if t < self.t_kink {
            1.0
        } else {
            1.0 - 3.0 * (t - self.t_kink)
        })
    }
}

#[test]
fn time_stops_are_hit_exactly() {
    let t_kink = 0.333_7;
    let opts = SolverOptions {
        time_stops: vec![t_kink],
        output: Output::Steps,
        ..Default::default()
    };
    let sol = solve(&mut Kink { t_kink }, 0.0, State::<1>::new(0.0), 1.0, &opts);
    assert_eq!(sol.status, Status::Success);
    assert!(sol.ts.contains(&t_kink), "{:?}", sol.ts);
    assert_eq!(sol.stats.time_stops, 1);
    let exact = 1.0 - 1.5 * (1.0 - t_kink) * (1.0 - t_kink);
    assert!((sol.y[0] - exact).abs() < 1e-14, "{} vs {exact}", sol.y[0]);
    // Without the stop a step crosses the kink and the answer is only within tolerance.
    let opts = SolverOptions {
        output: Output::Steps,
        ..Default::default()
    };
    let sol = solve(&mut Kink { t_kink }, 0.0, State::<1>::new(0.0), 1.0, &opts);
    assert!(!sol.ts.contains(&t_kink));
    assert!((sol.y[0] - exact).abs() > 1e-14);
}

#[test]
fn time_stops_added_while_integrating_are_hit_exactly() {
    for method in [Method::Dp5, Method::Rk4, Method::Euler] {
        let mut sys = ScheduledBrake::new(0.07);
        let opts = SolverOptions {
            method,
            fixed_step: 0.013,
            output: Output::Steps,
            ..Default::default()
        };
        let sol = solve(&mut sys, 0.0, State::<2>::new(0.0, 2.0), 1.0, &opts);
        assert_eq!(sol.status, Status::Success, "{method:?}");
        let t_stop = sys.stop_time.unwrap();
        assert!((t_stop - 0.57).abs() < 1e-12, "{method:?}: {t_stop}");
        assert!(sol.ts.contains(&t_stop), "{method:?}");
        // After braking: v = 2 - (t - t_stop); x = 2 t_stop + 2 (1 - t_stop) - (1 - t_stop)^2 / 2.
        let d = 1.0 - t_stop;
        assert!((sol.y[1] - (2.0 - d)).abs() < 1e-12, "{method:?}");
        if method != Method::Euler {
            // Quadratic in t: exact for DP5 and RK4 (Euler is only first order).
            assert!((sol.y[0] - (2.0 - d * d / 2.0)).abs() < 1e-12, "{method:?}");
        }
    }
}

/// Two event functions that cross at the same instant, both handled in index order.
struct Simultaneous {
    order: Vec<usize>,
}

impl OdeSystem<1> for Simultaneous {
    fn rhs(&self, _t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(1.0)
    }
    fn event_count(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, y: &State<1>, g: &mut [f64]) {
        g[0] = y[0] - 0.25;
        g[1] = 2.0 * (y[0] - 0.25);
    }
    fn on_event(
        &mut self,
        i: usize,
        _t: f64,
        _y: &mut State<1>,
        _ctl: &mut Control,
    ) -> EventAction {
        self.order.push(i);
        EventAction::Continue
    }
}

#[test]
fn simultaneous_events_are_all_handled_in_order() {
    let mut sys = Simultaneous { order: vec![] };
    let sol = solve(
        &mut sys,
        0.0,
        State::<1>::new(0.0),
        1.0,
        &SolverOptions::default(),
    );
    assert_eq!(sys.order, vec![0, 1]);
    assert_eq!(sol.events.len(), 2);
    assert_eq!(sol.events[0].t, sol.events[1].t);
}

/// `y' = -y`, but the right-hand side is undefined (NaN) below -0.5: a trial stage of a big
/// step leaves the domain though the solution never does.
struct Domain;

impl OdeSystem<1> for Domain {
    fn rhs(&self, _t: f64, y: &State<1>) -> State<1> {
        State::<1>::new(if y[0] < -0.5 { f64::NAN } else { -y[0] })
    }
}

#[test]
fn a_non_finite_trial_stage_is_rejected_and_retried_smaller() {
    let opts = SolverOptions {
        h0: Some(10.0),
        rtol: Tolerance::Scalar(1e-9),
        atol: Tolerance::Scalar(1e-12),
        ..Default::default()
    };
    let sol = solve(&mut Domain, 0.0, State::<1>::new(1.0), 5.0, &opts);
    assert_eq!(sol.status, Status::Success);
    assert!(sol.stats.rejected >= 1);
    assert!((sol.y[0] - (-5f64).exp()).abs() < 1e-9);
}

struct NanAfter {
    t_bad: f64,
}

impl OdeSystem<1> for NanAfter {
    fn rhs(&self, t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(if t > self.t_bad { f64::NAN } else { 1.0 })
    }
}

#[test]
fn a_right_hand_side_that_returns_nan_gives_a_status_not_a_panic() {
    let sol = solve(
        &mut NanAfter { t_bad: 0.5 },
        0.0,
        State::<1>::new(0.0),
        1.0,
        &SolverOptions::default(),
    );
    assert_eq!(sol.status, Status::StepTooSmall, "{}", sol.message);
    assert!((sol.t - 0.5).abs() < 1e-6, "stopped at {}", sol.t);
    let euler = SolverOptions {
        method: Method::Euler,
        fixed_step: 0.01,
        ..Default::default()
    };
    let sol = solve(
        &mut NanAfter { t_bad: 0.5 },
        0.0,
        State::<1>::new(0.0),
        1.0,
        &euler,
    );
    assert_eq!(sol.status, Status::NonFinite);
    let sol = solve(
        &mut NanAfter { t_bad: -1.0 },
        0.0,
        State::<1>::new(0.0),
        1.0,
        &SolverOptions::default(),
    );
    assert_eq!(sol.status, Status::NonFinite);
}

#[test]
fn bad_settings_give_invalid_input() {
    let opts = SolverOptions {
        rtol: Tolerance::Scalar(-1.0),
        ..Default::default()
    };
    let sol = solve(&mut Domain, 0.0, State::<1>::new(1.0), 5.0, &opts);
    assert_eq!(sol.status, Status::InvalidInput);
    assert!(sol.message.contains("rtol"));
    let sol = solve(
        &mut Domain,
        1.0,
        State::<1>::new(1.0),
        0.0,
        &SolverOptions::default(),
    );
    assert_eq!(sol.status, Status::InvalidInput);
}

#[test]
fn step_limit_gives_max_steps() {
    let opts = SolverOptions {
        max_steps: 5,
        rtol: Tolerance::Scalar(1e-12),
        atol: Tolerance::Scalar(1e-12),
        ..Default::default()
    };
    let sol = solve(
        &mut cushion_ode::test_models::exponential::Oscillator,
        0.0,
        State::<2>::new(1.0, 0.0),
        100.0,
        &opts,
    );
    assert_eq!(sol.status, Status::MaxSteps);
}

#[test]
fn output_at_requested_times_uses_the_dense_output() {
    let times: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    let opts = SolverOptions {
        output: Output::Times(times.clone()),
        rtol: Tolerance::Scalar(1e-10),
        atol: Tolerance::Scalar(1e-12),
        ..Default::default()
    };
    let sol = solve(
        &mut cushion_ode::test_models::exponential::Oscillator,
        0.0,
        State::<2>::new(1.0, 0.0),
        10.0,
        &opts,
    );
    assert_eq!(sol.ts, times);
    for (t, y) in sol.ts.iter().zip(&sol.ys) {
        assert!((y[0] - t.cos()).abs() < 1e-8, "t = {t}");
    }
    let plain = SolverOptions {
        output: Output::None,
        ..opts.clone()
    };
    let without = solve(
        &mut cushion_ode::test_models::exponential::Oscillator,
        0.0,
        State::<2>::new(1.0, 0.0),
        10.0,
        &plain,
    );
    assert_eq!(
        sol.stats, without.stats,
        "output points must not change the steps"
    );
}

#[test]
fn per_component_tolerances_are_used() {
    use cushion_ode::test_models::exponential::Exponential;
    let mut sys = Exponential {
        lambda: [-1.0, -2.0],
    };
    let loose = SolverOptions {
        rtol: Tolerance::PerComponent(vec![1e-3, 1e-3]),
        atol: Tolerance::Scalar(1e-12),
        ..Default::default()
    };
    let tight = SolverOptions {
        rtol: Tolerance::PerComponent(vec![1e-3, 1e-10]),
        atol: Tolerance::Scalar(1e-12),
        ..Default::default()
    };
    let y0 = State::<2>::new(1.0, 1.0);
    let a = solve(&mut sys, 0.0, y0, 3.0, &loose);
    let b = solve(&mut sys, 0.0, y0, 3.0, &tight);
    assert!(b.stats.steps > 2 * a.stats.steps);
    let exact = sys.exact(3.0, &y0);
    assert!((b.y[1] - exact[1]).abs() < 1e-9);
    let wrong = SolverOptions {
        rtol: Tolerance::PerComponent(vec![1e-3]),
        ..Default::default()
    };
    assert_eq!(
        solve(&mut sys, 0.0, y0, 3.0, &wrong).status,
        Status::InvalidInput
    );
}

/// `y' = 1` with one event at `y = at`, whose handler asks for time stops `at + delays[k]` and
/// answers `action`: the stops reached are recorded.
struct StopsFromAnEvent {
    at: f64,
    delays: Vec<f64>,
    action: EventAction,
    reached: Vec<f64>,
}

impl OdeSystem<1> for StopsFromAnEvent {
    fn rhs(&self, _t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(1.0)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<1>, g: &mut [f64]) {
        g[0] = y[0] - self.at;
    }
    fn on_event(&mut self, _i: usize, t: f64, _y: &mut State<1>, ctl: &mut Control) -> EventAction {
        for d in &self.delays {
            ctl.add_time_stop(t + d);
        }
        self.action
    }
    fn on_time_stop(&mut self, t: f64, _y: &mut State<1>, _ctl: &mut Control) -> EventAction {
        self.reached.push(t);
        EventAction::Continue
    }
}

/// The stops reached from `t = 0` to 1, which `y' = 1` covers in one step.
fn stops_reached(at: f64, delays: Vec<f64>, action: EventAction) -> Vec<f64> {
    let mut sys = StopsFromAnEvent {
        at,
        delays,
        action,
        reached: Vec::new(),
    };
    let sol = solve(
        &mut sys,
        0.0,
        State::<1>::new(0.0),
        1.0,
        &SolverOptions::default(),
    );
    assert_eq!(sol.status, Status::Success);
    assert_eq!(sol.stats.time_stops as usize, sys.reached.len());
    sys.reached
}

#[test]
fn a_handler_may_schedule_any_number_of_time_stops() {
    // the handler cuts the step (Restart), so all 20 stops lie ahead
    let delays: Vec<f64> = (1..=20).map(|k| 0.01 * k as f64).collect();
    let reached = stops_reached(0.5, delays.clone(), EventAction::Restart);
    assert_eq!(reached.len(), 20);
    for (got, d) in reached.iter().zip(&delays) {
        assert!((got - (0.5 + d)).abs() < 1e-15, "{got} vs {}", 0.5 + d);
    }
}

#[test]
fn a_time_stop_asked_for_inside_the_step_is_kept() {
    // the handler keeps the step from 0 to 1 (Continue) but asks for a stop at 0.35 inside it
    let reached = stops_reached(0.25, vec![0.1], EventAction::Continue);
    assert_eq!(reached.len(), 1, "{reached:?}");
    assert!((reached[0] - 0.35).abs() < 1e-15, "{reached:?}");
}

#[test]
fn a_function_zero_where_a_handler_left_it_takes_the_side_it_moves_to() {
    use cushion_ode::test_models::bouncing_ball::BouncingBall;
    // A ball on the floor (x = 0, the event function exactly zero) thrown up at 1e-3 m/s
    // lands at 2 v / g = 2.04e-4 s; the step sizes are free to span the whole flight (the
    // fall is a quadratic, integrated exactly, so the first step is as long as h0 allows).
    // The function is zero where the run starts and where each bounce's handler leaves it;
    // looked at a moment later it is positive, so every landing is a falling crossing.
    let mut ball = BouncingBall {
        gravity: 9.81,
        restitution: 0.5,
        stop_after: 3,
        bounces: 0,
    };
    let opts = SolverOptions {
        h0: Some(1.0),
        ..SolverOptions::default()
    };
    let sol = solve(&mut ball, 0.0, State::<2>::new(0.0, 1e-3), 1.0, &opts);
    assert_eq!(sol.status, Status::StoppedByEvent, "{}", sol.message);
    let flight = |v: f64| 2.0 * v / 9.81;
    let exact = [
        flight(1e-3),
        flight(1e-3) + flight(5e-4),
        flight(1e-3) + flight(5e-4) + flight(2.5e-4),
    ];
    let times: Vec<f64> = sol.events.iter().map(|e| e.t).collect();
    assert_eq!(times.len(), 3, "{times:?}");
    for (t, e) in times.iter().zip(exact) {
        assert!((t - e).abs() < 1e-12, "{times:?} vs {exact:?}");
    }
}
