//! Events, time stops and output under Rodas4 (`Method::Rodas`): the same loop as DOPRI5, so
//! crossings inside implicit steps are located on the dense output as precisely.

use cushion_ode::test_models::bouncing_ball::ten_bounces;
use cushion_ode::test_models::exponential::Oscillator;
use cushion_ode::test_models::scheduled_brake::ScheduledBrake;
use cushion_ode::{solve, Method, OdeSystem, Output, SolverOptions, State, Status, Tolerance};

fn rodas(tol: f64) -> SolverOptions {
    SolverOptions {
        method: Method::Rodas,
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        ..Default::default()
    }
}

#[test]
fn bouncing_ball_bounce_times_match_the_closed_form() {
    // The ball gives no Jacobian and no df/dt: both come from finite differences, exact here
    // (f is linear in y, constant in t). With an exact Jacobian a Rosenbrock method of order 4
    // integrates the quadratic fall exactly, and its continuous extension of order 3 is exact
    // on it too, so the root finder sees the true height.
    let (sol, exact) = ten_bounces(&rodas(1e-10));
    assert_eq!(sol.status, Status::StoppedByEvent);
    assert_eq!(sol.events.len(), 10);
    for (ev, t) in sol.events.iter().zip(&exact) {
        assert!((ev.t - t).abs() < 1e-12, "bounce at {} vs {}", ev.t, t);
        assert!(!ev.rising);
    }
    // One Jacobian per starting point: a restart at each bounce drops the old one.
    assert_eq!(sol.stats.jacobian_evals, sol.stats.steps);
    assert_eq!(
        sol.stats.lu_decompositions,
        sol.stats.steps + sol.stats.rejected
    );
}

#[test]
fn time_stops_added_while_integrating_are_hit_exactly() {
    let mut sys = ScheduledBrake::new(0.07);
    // The solution is piecewise linear-quadratic, so the error estimate vanishes and the steps
    // grow six-fold each; h_max keeps the stop (0.07 after the event) beyond the step in which
    // the event is found, since a stop scheduled inside an already accepted step is dropped.
    let opts = SolverOptions {
        output: Output::Steps,
        h_max: 0.05,
        ..rodas(1e-8)
    };
    let sol = solve(&mut sys, 0.0, State::<2>::new(0.0, 2.0), 1.0, &opts);
    assert_eq!(sol.status, Status::Success);
    let t_stop = sys.stop_time.unwrap();
    assert!((t_stop - 0.57).abs() < 1e-12, "{t_stop}");
    assert!(sol.ts.contains(&t_stop));
    assert_eq!(sol.stats.time_stops, 1);
    // Quadratic in t: exact for a 4th-order Rosenbrock method with its exact Jacobian.
    let d = 1.0 - t_stop;
    assert!((sol.y[1] - (2.0 - d)).abs() < 1e-12);
    assert!((sol.y[0] - (2.0 - d * d / 2.0)).abs() < 1e-12);
}

#[test]
fn output_at_requested_times_uses_the_dense_output_and_changes_no_step() {
    let times: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    let opts = SolverOptions {
        output: Output::Times(times.clone()),
        ..rodas(1e-9)
    };
    let sol = solve(&mut Oscillator, 0.0, State::<2>::new(1.0, 0.0), 10.0, &opts);
    assert_eq!(sol.ts, times);
    for (t, y) in sol.ts.iter().zip(&sol.ys) {
        // The continuous extension is of order 3: inside a step it is less accurate than the
        // steps' ends (1e-8 here), still within 10 times the tolerance.
        assert!((y[0] - t.cos()).abs() < 1e-8, "t = {t}: {}", y[0] - t.cos());
    }
    let plain = SolverOptions {
        output: Output::None,
        ..opts.clone()
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

/// `y' = -y`, with `f` undefined (NaN) below -0.5: a big trial step leaves the domain.
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
        ..rodas(1e-9)
    };
    let sol = solve(&mut Domain, 0.0, State::<1>::new(1.0), 5.0, &opts);
    assert_eq!(sol.status, Status::Success, "{}", sol.message);
    assert!(sol.stats.rejected >= 1);
    assert!((sol.y[0] - (-5f64).exp()).abs() < 1e-8);
}

/// `y' = lambda y` with `lambda = 4`: for `h = 1` the iteration matrix `I / (h gamma) - J`
/// (`gamma = 1/4`) is exactly zero.
struct Growth;

impl OdeSystem<1> for Growth {
    fn rhs(&self, _t: f64, y: &State<1>) -> State<1> {
        y * 4.0
    }
    fn jacobian(&self, _t: f64, _y: &State<1>) -> Option<cushion_ode::Matrix<1>> {
        Some(cushion_ode::Matrix::<1>::new(4.0))
    }
}

#[test]
fn a_singular_iteration_matrix_is_retried_with_a_smaller_step_and_counted() {
    let opts = SolverOptions {
        h0: Some(1.0),
        ..rodas(1e-8)
    };
    let sol = solve(&mut Growth, 0.0, State::<1>::new(1.0), 1.0, &opts);
    assert_eq!(sol.status, Status::Success, "{}", sol.message);
    assert_eq!(sol.stats.failed_solves, 1);
    assert!(sol.stats.rejected >= 1);
    assert!((sol.y[0] / 4f64.exp() - 1.0).abs() < 1e-7);
}

#[test]
fn the_stiffness_test_stays_silent_under_rodas() {
    // Hairer's test belongs to DOPRI5; the implicit method reports no estimate.
    let opts = SolverOptions {
        stiffness: cushion_ode::StiffnessAction::Stop,
        ..rodas(1e-6)
    };
    let sol = solve(
        &mut cushion_ode::test_models::van_der_pol::VanDerPol { mu: 1000.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        1.0,
        &opts,
    );
    assert_eq!(sol.status, Status::Success);
    assert!(!sol.stats.stiff);
}
