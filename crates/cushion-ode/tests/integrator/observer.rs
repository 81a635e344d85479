//! The observer beside the problem (`observer.rs`, `solve_observed`): it sees every accepted
//! step, each instant of events and each time stop once, with the problem as the handlers left
//! it, changes nothing, and can end the run.

use cushion_ode::test_models::scheduled_brake::ScheduledBrake;
use cushion_ode::{
    solve, solve_observed, Control, Method, Observer, Solution, SolverOptions, State, Status, Step,
    Tolerance,
};

#[derive(Default)]
struct Watch {
    steps: u64,
    last_t1: f64,
    event_instants: usize,
    /// Whether the brake was on when the observer saw the time stop: before / after it.
    braking_around_stop: Vec<(bool, bool)>,
    before: Option<bool>,
    /// End the run after this many steps.
    stop_after: Option<u64>,
}

impl Observer<ScheduledBrake, 2> for Watch {
    fn on_step(&mut self, _sys: &ScheduledBrake, step: &Step<'_, 2>) {
        assert!(
            step.t0 == self.last_t1 || self.steps == 0,
            "steps follow each other"
        );
        self.steps += 1;
        self.last_t1 = step.t1;
    }
    fn after_step(&mut self, _sys: &ScheduledBrake, _step: &Step<'_, 2>, ctl: &mut Control) {
        if self.stop_after == Some(self.steps) {
            ctl.stop();
        }
    }
    fn after_events(&mut self, sys: &ScheduledBrake) {
        assert!(
            sys.stop_time.is_some(),
            "the handler ran before the observer"
        );
        self.event_instants += 1;
    }
    fn before_time_stop(&mut self, sys: &ScheduledBrake) {
        self.before = Some(sys.braking);
    }
    fn after_time_stop(
        &mut self,
        sys: &ScheduledBrake,
        _t: f64,
        _y: &State<2>,
        _ctl: &mut Control,
    ) {
        let before = self.before.take().expect("before_time_stop came first");
        self.braking_around_stop.push((before, sys.braking));
    }
    fn after_switch(&mut self, _sys: &ScheduledBrake, _to: Method) {}
}

fn opts(method: Method) -> SolverOptions {
    SolverOptions {
        method,
        rtol: Tolerance::Scalar(1e-8),
        atol: Tolerance::Scalar(1e-10),
        ..Default::default()
    }
}

#[test]
fn an_observer_sees_every_step_event_and_time_stop_and_changes_nothing() {
    for method in [Method::Dp5, Method::Dop853, Method::Rodas, Method::Auto] {
        let y0 = State::<2>::new(0.0, 2.0);
        let plain = solve(&mut ScheduledBrake::new(0.07), 0.0, y0, 1.0, &opts(method));
        let mut watch = Watch::default();
        let mut sys = ScheduledBrake::new(0.07);
        let seen = solve_observed(&mut sys, &mut watch, 0.0, y0, 1.0, &opts(method));
        assert_eq!(seen.status, Status::Success, "{method:?}");
        assert_eq!(
            (seen.t, seen.y),
            (plain.t, plain.y),
            "{method:?}: same solution"
        );
        assert_eq!(seen.stats.steps, plain.stats.steps, "{method:?}");
        assert_eq!(
            watch.steps, seen.stats.steps,
            "{method:?}: every accepted step"
        );
        assert_eq!(watch.last_t1, 1.0, "{method:?}");
        assert_eq!(watch.event_instants, 1, "{method:?}: x = 1 crossed once");
        assert_eq!(watch.braking_around_stop, [(false, true)], "{method:?}");
    }
}

#[test]
fn an_observer_can_end_the_run() {
    let mut watch = Watch {
        stop_after: Some(5),
        ..Default::default()
    };
    let mut sys = ScheduledBrake::new(0.07);
    let y0 = State::<2>::new(0.0, 2.0);
    let sol = solve_observed(&mut sys, &mut watch, 0.0, y0, 1.0, &opts(Method::Dp5));
    assert_eq!(sol.status, Status::StoppedByEvent);
    assert_eq!(sol.stats.steps, 5);
    assert_eq!(sol.t, watch.last_t1, "it ends where the fifth step ends");
}

/// The scheduled brake from rest under DOPRI5, watched by `watch`.
fn brake_run<O: Observer<ScheduledBrake, 2>>(watch: &mut O) -> Solution<2> {
    let y0 = State::<2>::new(0.0, 2.0);
    solve_observed(
        &mut ScheduledBrake::new(0.07),
        watch,
        0.0,
        y0,
        1.0,
        &opts(Method::Dp5),
    )
}

#[test]
fn a_pair_of_observers_each_sees_every_hook_and_either_ends_the_run() {
    let y0 = State::<2>::new(0.0, 2.0);
    let plain = solve(
        &mut ScheduledBrake::new(0.07),
        0.0,
        y0,
        1.0,
        &opts(Method::Dp5),
    );
    let mut first = Watch::default();
    let mut absent: Option<Watch> = None;
    let mut pair = (&mut first, (&mut absent, Watch::default()));
    let seen = brake_run(&mut pair);
    let second = &pair.1 .1;
    assert_eq!((seen.t, seen.y), (plain.t, plain.y), "same solution");
    for watch in [&*pair.0, second] {
        assert_eq!(watch.steps, plain.stats.steps);
        assert_eq!(watch.event_instants, 1);
        assert_eq!(watch.braking_around_stop, [(false, true)]);
    }
    assert!(absent.is_none());

    // the second of the pair ends the run; the first still saw the step that ended it
    let mut first = Watch::default();
    let second = Watch {
        stop_after: Some(7),
        ..Default::default()
    };
    let mut pair = (&mut first, second);
    let sol = brake_run(&mut pair);
    assert_eq!(sol.status, Status::StoppedByEvent);
    assert_eq!((sol.stats.steps, first.steps), (7, 7));
}
