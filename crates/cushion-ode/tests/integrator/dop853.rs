//! Hairer's DOP853 (`Method::Dop853`): orders of the method and of its dense output, the
//! Arenstorf orbit against DOPRI5, events and time stops, the stiffness test, the count of
//! evaluations.

use cushion_ode::test_models::arenstorf::{initial_state, Arenstorf, PERIOD};
use cushion_ode::test_models::bouncing_ball::ten_bounces;
use cushion_ode::test_models::exponential::Oscillator;
use cushion_ode::test_models::manufactured::Manufactured;
use cushion_ode::test_models::scheduled_brake::ScheduledBrake;
use cushion_ode::test_models::van_der_pol::VanDerPol;
use cushion_ode::{
    solve, Method, OdeSystem, Output, SolverOptions, State, Status, StiffnessAction, Tolerance,
};

fn opts(method: Method, tol: f64) -> SolverOptions {
    SolverOptions {
        method,
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        max_steps: 10_000_000,
        ..Default::default()
    }
}

/// Every step accepted and of size `h`: tolerances so loose that the controller never binds.
fn fixed(h: f64) -> SolverOptions {
    SolverOptions {
        h0: Some(h),
        h_max: h,
        stiffness: StiffnessAction::Off,
        ..opts(Method::Dop853, 1e10)
    }
}

#[test]
fn the_name_is_dop853() {
    assert_eq!(Method::from_name("dop853"), Some(Method::Dop853));
    assert_eq!(Method::Dop853.name(), "dop853");
    assert!(Method::NAMES.contains(&"dop853"));
    assert!(Method::Dop853.is_adaptive());
}

/// Global error at `t_end` of the manufactured problem (nonlinear, non-autonomous: every
/// order condition counts) with the fixed step `h`.
fn global_error(h: f64) -> f64 {
    let t_end = 4.0;
    let sol = solve(
        &mut Manufactured,
        0.0,
        Manufactured::exact(0.0),
        t_end,
        &fixed(h),
    );
    assert_eq!(sol.status, Status::Success);
    assert_eq!(sol.stats.rejected, 0);
    (sol.y - Manufactured::exact(t_end)).amax()
}

#[test]
fn dop853_is_eighth_order() {
    let mut orders = Vec::new();
    for h in [0.4, 0.2] {
        let (e1, e2) = (global_error(h), global_error(h / 2.0));
        let p = (e1 / e2).log2();
        println!("h {h}: errors {e1:.3e} {e2:.3e}, order {p:.3}");
        orders.push(p);
    }
    for p in orders {
        assert!((7.5..8.5).contains(&p), "measured order {p}");
    }
}

/// Records the dense output at a fraction of the first step.
struct Probe<S> {
    inner: S,
    theta: f64,
    at: Option<State<2>>,
}

impl<S: OdeSystem<2>> OdeSystem<2> for Probe<S> {
    fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
        self.inner.rhs(t, y)
    }
    fn on_step(&mut self, step: &cushion_ode::Step<'_, 2>, _ctl: &mut cushion_ode::Control) {
        if self.at.is_none() {
            self.at = Some(step.at(step.t0 + self.theta * (step.t1 - step.t0)));
        }
    }
}

/// Local error of the dense output at `theta h` inside one step of size `h` from the exact
/// state.
fn dense_local_error(h: f64, theta: f64) -> f64 {
    let mut sys = Probe {
        inner: Manufactured,
        theta,
        at: None,
    };
    solve(&mut sys, 0.0, Manufactured::exact(0.0), h, &fixed(h));
    (sys.at.unwrap() - Manufactured::exact(theta * h)).amax()
}

#[test]
fn dense_output_is_seventh_order() {
    // A continuous extension of order 7 has local error O(h^8): ratio 2^8 when h halves
    // (measured: 7.74-7.80 from h = 0.2, 7.88-7.93 from h = 0.1, the errors then 1e-14).
    for theta in [0.3, 0.5, 0.8] {
        let e = [0.2, 0.1, 0.05].map(|h| dense_local_error(h, theta));
        let (p1, p2) = ((e[0] / e[1]).log2(), (e[1] / e[2]).log2());
        println!(
            "theta {theta}: local errors {:.3e} {:.3e} {:.3e}, exponents {p1:.3} {p2:.3}",
            e[0], e[1], e[2]
        );
        assert!(
            (7.5..8.5).contains(&p1),
            "theta {theta}: local exponent {p1}"
        );
        assert!(
            (p2 - 8.0).abs() < 0.25,
            "theta {theta}: local exponent {p2}"
        );
    }
}

#[test]
fn output_at_requested_times_is_as_accurate_as_the_steps() {
    let times: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    let o = SolverOptions {
        output: Output::Times(times.clone()),
        ..opts(Method::Dop853, 1e-12)
    };
    let sol = solve(&mut Oscillator, 0.0, State::<2>::new(1.0, 0.0), 10.0, &o);
    assert_eq!(sol.ts, times);
    let worst = sol
        .ts
        .iter()
        .zip(&sol.ys)
        .map(|(t, y)| (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs()))
        .fold(0.0, f64::max);
    println!("dense output error {worst:.2e}, {} steps", sol.stats.steps);
    assert!(worst < 1e-10, "{worst:e}");
    let plain = SolverOptions {
        output: Output::None,
        ..o.clone()
    };
    let without = solve(
        &mut Oscillator,
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
fn evaluations_are_counted_as_the_code_counts_them() {
    // f(t0, y0), one for the initial step, 11 per attempt, and per accepted step f(y1) and
    // the three stages of the dense output.
    let sol = solve(
        &mut Arenstorf,
        0.0,
        initial_state(),
        PERIOD,
        &opts(Method::Dop853, 1e-8),
    );
    assert_eq!(sol.status, Status::Success);
    let s = sol.stats;
    assert!(s.rejected > 0);
    assert_eq!(s.rhs_evals, 2 + 11 * (s.steps + s.rejected) + 4 * s.steps);
}

#[test]
fn arenstorf_closes_with_fewer_evaluations_than_dopri5() {
    let mut last = f64::INFINITY;
    println!("   tol   |  DOP853 error  evals (steps, rejected) |  DOPRI5 error  evals");
    for (tol, bound) in [(1e-9, 1e-5), (1e-10, 1e-6), (1e-11, 1e-7), (1e-12, 1e-8)] {
        let a = solve(
            &mut Arenstorf,
            0.0,
            initial_state(),
            PERIOD,
            &opts(Method::Dop853, tol),
        );
        let b = solve(
            &mut Arenstorf,
            0.0,
            initial_state(),
            PERIOD,
            &opts(Method::Dp5, tol),
        );
        assert_eq!(a.status, Status::Success);
        assert_eq!(b.status, Status::Success);
        let (ea, eb) = (
            (a.y - initial_state()).amax(),
            (b.y - initial_state()).amax(),
        );
        println!(
            "  {tol:.0e}  |  {ea:.2e}  {:>6} ({}, {})  |  {eb:.2e}  {:>6}",
            a.stats.rhs_evals, a.stats.steps, a.stats.rejected, b.stats.rhs_evals
        );
        assert!(ea < bound, "tol {tol:e}: error {ea:e} above {bound:e}");
        assert!(ea < last, "error must fall with the tolerance");
        last = ea;
        assert!(
            a.stats.rhs_evals < b.stats.rhs_evals,
            "tol {tol:e}: {} vs DOPRI5's {}",
            a.stats.rhs_evals,
            b.stats.rhs_evals
        );
        assert!(!a.stats.stiff, "Arenstorf is not stiff");
    }
}

#[test]
fn bouncing_ball_bounce_times_match_the_closed_form() {
    // The fall is quadratic in t: the method and its continuous extension are exact on it.
    let (sol, exact) = ten_bounces(&opts(Method::Dop853, 1e-10));
    assert_eq!(sol.status, Status::StoppedByEvent);
    assert_eq!(sol.events.len(), 10);
    for (ev, t) in sol.events.iter().zip(&exact) {
        assert!((ev.t - t).abs() < 1e-12, "bounce at {} vs {}", ev.t, t);
        assert!(!ev.rising);
    }
}

#[test]
fn time_stops_added_while_integrating_are_hit_exactly() {
    let mut sys = ScheduledBrake::new(0.07);
    // As under Rodas (tests/integrator/rodas_events.rs): the error estimate vanishes on the piecewise
    // quadratic solution, so h_max keeps the scheduled stop beyond the step that finds the
    // event.
    let o = SolverOptions {
        output: Output::Steps,
        h_max: 0.05,
        ..opts(Method::Dop853, 1e-8)
    };
    let sol = solve(&mut sys, 0.0, State::<2>::new(0.0, 2.0), 1.0, &o);
    assert_eq!(sol.status, Status::Success);
    let t_stop = sys.stop_time.unwrap();
    assert!((t_stop - 0.57).abs() < 1e-12, "{t_stop}");
    assert!(sol.ts.contains(&t_stop));
    assert_eq!(sol.stats.time_stops, 1);
    let d = 1.0 - t_stop;
    assert!((sol.y[1] - (2.0 - d)).abs() < 1e-12);
    assert!((sol.y[0] - (2.0 - d * d / 2.0)).abs() < 1e-12);
}

#[test]
fn stiffness_test_fires_on_van_der_pol_mu_1000_and_not_on_mu_1() {
    let stop = SolverOptions {
        stiffness: StiffnessAction::Stop,
        ..opts(Method::Dop853, 1e-6)
    };
    let sol = solve(
        &mut VanDerPol { mu: 1000.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        1.0,
        &stop,
    );
    assert_eq!(sol.status, Status::Stiff, "{}", sol.message);
    assert!(sol.t < 1.0);
    assert!(sol.message.contains("5.754"), "{}", sol.message);
    let sol = solve(
        &mut VanDerPol { mu: 1.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        20.0,
        &SolverOptions {
            stiffness: StiffnessAction::Stop,
            ..opts(Method::Dop853, 1e-8)
        },
    );
    assert_eq!(sol.status, Status::Success);
    assert!(!sol.stats.stiff);
}

/// `y' = -y`, with `f` undefined (NaN) below -0.5: a big trial step leaves the domain.
struct Domain;

impl OdeSystem<1> for Domain {
    fn rhs(&self, _t: f64, y: &State<1>) -> State<1> {
        State::<1>::new(if y[0] < -0.5 { f64::NAN } else { -y[0] })
    }
}

#[test]
fn a_non_finite_trial_stage_is_rejected_and_retried_smaller() {
    let o = SolverOptions {
        h0: Some(10.0),
        ..opts(Method::Dop853, 1e-9)
    };
    let sol = solve(&mut Domain, 0.0, State::<1>::new(1.0), 5.0, &o);
    assert_eq!(sol.status, Status::Success, "{}", sol.message);
    assert!(sol.stats.rejected >= 1);
    assert!((sol.y[0] - (-5f64).exp()).abs() < 1e-8);
}

/// `y' = lambda y` in one state, with the dense output read at every hundredth of the first
/// step.
struct DenseFactor {
    lambda: f64,
    at: Vec<f64>,
}

impl OdeSystem<1> for DenseFactor {
    fn rhs(&self, _t: f64, y: &State<1>) -> State<1> {
        State::<1>::new(self.lambda * y[0])
    }
    fn on_step(&mut self, step: &cushion_ode::Step<'_, 1>, _ctl: &mut cushion_ode::Control) {
        if self.at.is_empty() {
            self.at = (1..100)
                .map(|i| step.at(step.t0 + i as f64 / 100.0 * (step.t1 - step.t0))[0])
                .collect();
        }
    }
}

/// The largest `|P(theta, z)|` of a method's dense output over one step of `y' = z y`, `h = 1`.
fn largest_dense_factor(method: Method, z: f64) -> f64 {
    let mut sys = DenseFactor {
        lambda: z,
        at: Vec::new(),
    };
    let o = SolverOptions {
        method,
        ..fixed(1.0)
    };
    solve(&mut sys, 0.0, State::<1>::new(1.0), 1.0, &o);
    sys.at.iter().fold(0.0, |m, p| m.max(p.abs()))
}

#[test]
fn the_dense_output_is_stable_up_to_its_boundary_and_not_beyond() {
    use cushion_ode::dop853::{DENSE_STABILITY_BOUNDARY, STABILITY_BOUNDARY};
    // DOP853's continuous extension keeps a decaying mode within its start up to h |lambda| =
    // 5 (measured 0.953 there), and amplifies it beyond, well inside the step's own stability
    // boundary of 6.39 (3.2 at 5.5, 10.5 at 6); DOPRI5's stays within it up to 3 (0.969).
    let at_boundary = largest_dense_factor(Method::Dop853, -DENSE_STABILITY_BOUNDARY);
    let beyond = largest_dense_factor(Method::Dop853, -5.5);
    let near_step_boundary = largest_dense_factor(Method::Dop853, -0.94 * STABILITY_BOUNDARY);
    let dp5 = largest_dense_factor(Method::Dp5, -3.0);
    println!("DOP853: {at_boundary:.3} at 5, {beyond:.3} at 5.5, {near_step_boundary:.3} at 6; DOPRI5: {dp5:.3} at 3");
    assert!(at_boundary <= 1.0, "{at_boundary}");
    assert!(beyond > 3.0, "{beyond}");
    assert!(near_step_boundary > 10.0, "{near_step_boundary}");
    assert!(dp5 <= 1.0, "{dp5}");
}

/// A slow decay beside a fast mode held on a slow forcing: `y0' = -y0`,
/// `y1' = -1e4 (y1 - cos t)`; counts the steps whose dense output is not stable.
struct FastMode {
    unstable: usize,
    steps: usize,
}

impl OdeSystem<2> for FastMode {
    fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(-y[0], -1e4 * (y[1] - t.cos()))
    }
    fn on_step(&mut self, step: &cushion_ode::Step<'_, 2>, _ctl: &mut cushion_ode::Control) {
        self.steps += 1;
        self.unstable += usize::from(!step.dense_stable);
    }
}

#[test]
fn steps_held_by_stability_say_their_dense_output_is_not_stable() {
    // Once the fast mode has settled on `cos t`, DOP853 steps at its stability boundary, h
    // about 6e-4: there its dense output is not stable, and the step says so. DOPRI5's always
    // is, and DOP853's on the oscillator, whose steps are held by accuracy.
    let count = |method: Method| {
        let mut sys = FastMode {
            unstable: 0,
            steps: 0,
        };
        let o = opts(method, 1e-6);
        let sol = solve(&mut sys, 0.0, State::<2>::new(1.0, 0.0), 1.0, &o);
        assert_eq!(sol.status, Status::Success);
        (sys.unstable, sys.steps)
    };
    let (dop853_unstable, dop853_steps) = count(Method::Dop853);
    let (dp5_unstable, dp5_steps) = count(Method::Dp5);
    println!("DOP853: {dop853_unstable} of {dop853_steps} steps not stable; DOPRI5: {dp5_unstable} of {dp5_steps}");
    assert!(dop853_steps > 1000, "{dop853_steps}");
    assert!(
        dop853_unstable * 10 > dop853_steps * 9,
        "{dop853_unstable} of {dop853_steps}"
    );
    assert_eq!(dp5_unstable, 0);
    struct Counted(usize);
    impl OdeSystem<2> for Counted {
        fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
            Oscillator.rhs(t, y)
        }
        fn on_step(&mut self, step: &cushion_ode::Step<'_, 2>, _ctl: &mut cushion_ode::Control) {
            self.0 += usize::from(!step.dense_stable);
        }
    }
    let mut osc = Counted(0);
    solve(
        &mut osc,
        0.0,
        State::<2>::new(1.0, 0.0),
        20.0,
        &opts(Method::Dop853, 1e-8),
    );
    assert_eq!(osc.0, 0);
}
