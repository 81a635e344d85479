//! Classic problems: Arenstorf orbit, bouncing ball, stiffness test.

use cushion_ode::test_models::arenstorf::{initial_state, Arenstorf, PERIOD};
use cushion_ode::test_models::bouncing_ball::ten_bounces;
use cushion_ode::test_models::robertson::Robertson;
use cushion_ode::test_models::van_der_pol::VanDerPol;
use cushion_ode::{solve, Method, SolverOptions, State, Status, StiffnessAction, Tolerance};

fn tol_opts(tol: f64) -> SolverOptions {
    SolverOptions {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        max_steps: 10_000_000,
        ..Default::default()
    }
}

#[test]
fn arenstorf_orbit_closes_after_one_period() {
    // Error after one period against the tolerance. The orbit passes close to the moon twice,
    // where errors are amplified; Hairer's DOPRI5 shows the same error level.
    let mut last = f64::INFINITY;
    for &(tol, bound) in &[(1e-7, 1e-2), (1e-10, 1e-5), (1e-13, 1e-8)] {
        let sol = solve(&mut Arenstorf, 0.0, initial_state(), PERIOD, &tol_opts(tol));
        assert_eq!(sol.status, Status::Success);
        let err = (sol.y - initial_state()).amax();
        assert!(err < bound, "tol {tol:e}: error {err:e} above {bound:e}");
        assert!(err < last, "error must fall with the tolerance");
        last = err;
        assert!(!sol.stats.stiff, "Arenstorf is not stiff");
    }
}

#[test]
fn bouncing_ball_first_ten_bounces_match_closed_form() {
    for method in [Method::Dp5, Method::Rk4] {
        let opts = SolverOptions {
            method,
            fixed_step: 0.01,
            ..tol_opts(1e-10)
        };
        let (sol, exact) = ten_bounces(&opts);
        assert_eq!(sol.status, Status::StoppedByEvent, "{method:?}");
        assert_eq!(sol.events.len(), 10, "{method:?}");
        for (ev, t) in sol.events.iter().zip(&exact) {
            assert!(
                (ev.t - t).abs() < 1e-12,
                "{method:?}: bounce at {} vs {}",
                ev.t,
                t
            );
            assert!(!ev.rising);
        }
    }
}

#[test]
fn stiffness_test_fires_on_van_der_pol_mu_1000() {
    let opts = SolverOptions {
        stiffness: StiffnessAction::Warn,
        ..tol_opts(1e-6)
    };
    let sol = solve(
        &mut VanDerPol { mu: 1000.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        1.0,
        &opts,
    );
    assert!(sol.status.is_ok(), "{:?}", sol.status);
    assert!(sol.stats.stiff);
    let since = sol.stats.stiff_since.unwrap();
    assert!((0.0..1.0).contains(&since));

    let stop = SolverOptions {
        stiffness: StiffnessAction::Stop,
        ..tol_opts(1e-6)
    };
    let sol = solve(
        &mut VanDerPol { mu: 1000.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        1.0,
        &stop,
    );
    assert_eq!(sol.status, Status::Stiff);
    assert!(sol.t < 1.0);
}

#[test]
fn stiffness_test_fires_on_robertson() {
    let opts = SolverOptions {
        stiffness: StiffnessAction::Stop,
        ..tol_opts(1e-6)
    };
    let sol = solve(
        &mut Robertson,
        0.0,
        State::<3>::new(1.0, 0.0, 0.0),
        1e3,
        &opts,
    );
    assert_eq!(sol.status, Status::Stiff);
}

#[test]
fn stiffness_test_is_silent_on_non_stiff_problems() {
    let sol = solve(
        &mut VanDerPol { mu: 1.0 },
        0.0,
        State::<2>::new(2.0, 0.0),
        20.0,
        &tol_opts(1e-8),
    );
    assert_eq!(sol.status, Status::Success);
    assert!(!sol.stats.stiff);
}
