//! Kinks (`kinks.rs`): DOP853 ends its steps at the forecast zeros of a system's kink
//! functions, and so meets its tolerance with fewer evaluations and rejections where `f` has
//! a jump in a higher derivative; the other methods ignore them; a kink is never an event.

use cushion_ode::kinks::MAX_KINKS;
use cushion_ode::test_models::kinked_power::KinkedPower;
use cushion_ode::{
    solve, Method, OdeSystem, Output, Solution, SolverOptions, State, Status, Tolerance,
};
use std::f64::consts::PI;

/// Nine kinks: `v = -sin t` changes sign at `k pi`, `k = 1..9`.
const T_END: f64 = 30.0;

fn opts(method: Method, tol: f64) -> SolverOptions {
    SolverOptions {
        method,
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        output: Output::Steps,
        ..Default::default()
    }
}

fn run(kinks: bool, method: Method, tol: f64) -> Solution<3> {
    let y0 = KinkedPower::exact(0.0);
    let sol = solve(
        &mut KinkedPower { kinks },
        0.0,
        y0,
        T_END,
        &opts(method, tol),
    );
    assert_eq!(sol.status, Status::Success, "{}", sol.message);
    sol
}

fn error(sol: &Solution<3>) -> f64 {
    (sol.y - KinkedPower::exact(T_END)).amax()
}

/// Across a kink an embedded pair's two solutions share their stages, and its estimate misses
/// most of the kink's error: without landing, DOP853 ends 38 to 268 times its tolerance off
/// (the work `z` keeps every kink's error), and is rejected at most kinks. Landing on them,
/// it is within 3.9 times its tolerance (1e-6 to 1e-12), with a third to a tenth of the
/// rejections and 19 to 37 % fewer evaluations.
#[test]
fn dop853_landing_on_kinks_meets_its_tolerance_for_less_work() {
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let (over, landed) = (
            run(false, Method::Dop853, tol),
            run(true, Method::Dop853, tol),
        );
        let (e_over, e_landed) = (error(&over), error(&landed));
        assert!(e_landed < 5.0 * tol, "tol {tol:e}: {e_landed:e}");
        assert!(
            e_over > 30.0 * tol,
            "tol {tol:e}: {e_over:e} (the test lost its point)"
        );
        assert!(
            2 * landed.stats.rejected < over.stats.rejected,
            "tol {tol:e}: rejected {} against {}",
            landed.stats.rejected,
            over.stats.rejected
        );
        assert!(
            landed.stats.rhs_evals < over.stats.rhs_evals * 85 / 100,
            "tol {tol:e}: {} evaluations against {}",
            landed.stats.rhs_evals,
            over.stats.rhs_evals
        );
        // never located, logged or handled
        assert!(landed.events.is_empty());
        assert_eq!(landed.stats.events, 0);
    }
}

/// Each kink ends a step: the step end nearest to `k pi` is within a thousandth of the two
/// steps around it (the forecast's error, or a crossing forecast a sliver of a step ahead,
/// which the next step runs over; at most 3.2e-4 here). A kink that near a step's end adds
/// about a billionth of the error it would in the step's middle.
#[test]
fn each_kink_ends_a_step() {
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let sol = run(true, Method::Dop853, tol);
        let ts = &sol.ts;
        for k in 1..=9 {
            let kink = k as f64 * PI;
            let i = ts.partition_point(|&t| t < kink);
            let span = ts[i + 1] - ts[i - 1];
            let nearest = (ts[i] - kink).abs().min((ts[i - 1] - kink).abs());
            assert!(
                nearest < 1e-3 * span,
                "tol {tol:e}, kink {k}: {nearest:e} of {span:e}"
            );
        }
    }
}

/// The methods that do not land on kinks (DOPRI5, Rodas, `auto`) run the same to the bit with
/// or without them.
#[test]
fn the_other_methods_ignore_kinks() {
    for method in [Method::Dp5, Method::Rodas, Method::Auto] {
        let (a, b) = (run(false, method, 1e-8), run(true, method, 1e-8));
        assert_eq!(a.ts, b.ts, "{method:?}");
        assert_eq!(a.ys, b.ys, "{method:?}");
        assert_eq!(a.stats.rhs_evals, b.stats.rhs_evals, "{method:?}");
    }
}

/// More kink functions than the loop follows: refused, not cut short.
struct TooManyKinks;

impl OdeSystem<1> for TooManyKinks {
    fn rhs(&self, _t: f64, _y: &State<1>) -> State<1> {
        State::<1>::new(1.0)
    }
    fn kink_count(&self) -> usize {
        MAX_KINKS + 1
    }
}

#[test]
fn more_kinks_than_allowed_are_refused() {
    let sol = solve(
        &mut TooManyKinks,
        0.0,
        State::<1>::new(0.0),
        1.0,
        &opts(Method::Dop853, 1e-6),
    );
    assert_eq!(sol.status, Status::InvalidInput);
    assert!(sol.message.contains("kink"), "{}", sol.message);
}
