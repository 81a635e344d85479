//! Rodas4 (`Method::Rodas`): convergence orders measured on a nonlinear, non-autonomous
//! problem with a known solution (`test_models::manufactured`).

use cushion_ode::test_models::manufactured::Manufactured;
use cushion_ode::{
    solve, Control, Method, OdeSystem, SolverOptions, State, Status, Step, StiffnessAction,
    Tolerance,
};

fn rodas(rtol: f64, atol: f64) -> SolverOptions {
    SolverOptions {
        method: Method::Rodas,
        rtol: Tolerance::Scalar(rtol),
        atol: Tolerance::Scalar(atol),
        stiffness: StiffnessAction::Off,
        ..Default::default()
    }
}

/// Global error at t = 2 with every step of size `h` (tolerances so loose the controller never
/// binds; `h_max` holds the step).
fn fixed_step_error(h: f64) -> f64 {
    let opts = SolverOptions {
        h0: Some(h),
        h_max: h,
        ..rodas(1e10, 1e10)
    };
    let sol = solve(&mut Manufactured, 0.0, Manufactured::exact(0.0), 2.0, &opts);
    assert_eq!(sol.status, Status::Success);
    assert_eq!(sol.stats.rejected, 0);
    (sol.y - Manufactured::exact(2.0)).norm()
}

#[test]
fn rodas_is_fourth_order() {
    let e: Vec<f64> = [0.025, 0.0125, 0.00625]
        .iter()
        .map(|&h| fixed_step_error(h))
        .collect();
    println!("errors {e:?}");
    for w in e.windows(2) {
        let p = (w[0] / w[1]).log2();
        assert!((p - 4.0).abs() < 0.1, "measured order {p}: errors {e:?}");
    }
}

/// Records the dense output at the middle of the first step.
struct MidStep {
    mid: Option<State<2>>,
}

impl OdeSystem<2> for MidStep {
    fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
        Manufactured.rhs(t, y)
    }
    fn jacobian(&self, t: f64, y: &State<2>) -> Option<cushion_ode::Matrix<2>> {
        Manufactured.jacobian(t, y)
    }
    fn on_step(&mut self, step: &Step<'_, 2>, _ctl: &mut Control) {
        if self.mid.is_none() {
            self.mid = Some(step.at(0.5 * (step.t0 + step.t1)));
        }
    }
}

fn dense_local_error(h: f64) -> f64 {
    let opts = SolverOptions {
        h0: Some(h),
        h_max: h,
        ..rodas(1e10, 1e10)
    };
    let mut sys = MidStep { mid: None };
    solve(&mut sys, 0.0, Manufactured::exact(0.0), h, &opts);
    (sys.mid.unwrap() - Manufactured::exact(0.5 * h)).norm()
}

#[test]
fn dense_output_is_third_order() {
    // A continuous extension of order 3 has local error O(h^4): ratio 2^4 when h halves.
    // Measured: 4.40e-8 and 2.79e-9 at the middle of a step of 0.025 and 0.0125: exponent 3.98.
    let (a, b) = (dense_local_error(0.025), dense_local_error(0.0125));
    let p = (a / b).log2();
    assert!((p - 4.0).abs() < 0.25, "local exponent {p}");
}

#[test]
fn error_falls_with_the_tolerance() {
    // Over [0, 10] with rtol = atol = tol: measured errors 1.03e-5, 1.12e-7, 1.17e-9, 1.19e-11
    // at tol = 1e-4, 1e-6, 1e-8, 1e-10: about 0.1 tol each, proportional to it (slope 0.98-0.99
    // a decade).
    let err = |tol: f64| {
        let sol = solve(
            &mut Manufactured,
            0.0,
            Manufactured::exact(0.0),
            10.0,
            &rodas(tol, tol),
        );
        assert_eq!(sol.status, Status::Success);
        (sol.y - Manufactured::exact(10.0)).amax()
    };
    let tols = [1e-4, 1e-6, 1e-8, 1e-10];
    let errs: Vec<f64> = tols.iter().map(|&t| err(t)).collect();
    for (tol, e) in tols.iter().zip(&errs) {
        assert!(*e < *tol, "tol {tol:e}: error {e:e}");
    }
    for w in errs.windows(2) {
        let slope = (w[0] / w[1]).log10() / 2.0;
        assert!(slope > 0.9 && slope < 1.1, "slope {slope}: {errs:?}");
    }
}
