//! Convergence orders measured from error ratios as the step halves.

use cushion_ode::test_models::exponential::Oscillator;
use cushion_ode::{solve, Method, OdeSystem, SolverOptions, State, StiffnessAction, Tolerance};

/// Global error at t = 2 of the oscillator (exact: cos t, -sin t) with a fixed step `h`.
fn global_error(method: Method, h: f64) -> f64 {
    let mut opts = SolverOptions {
        method,
        stiffness: StiffnessAction::Off,
        ..Default::default()
    };
    if method == Method::Dp5 {
        // Every step accepted and of size h: the controller never binds.
        opts.h0 = Some(h);
        opts.h_max = h;
        opts.rtol = Tolerance::Scalar(1e10);
        opts.atol = Tolerance::Scalar(1e10);
    } else {
        opts.fixed_step = h;
    }
    let t_end = 2.0;
    let sol = solve(
        &mut Oscillator,
        0.0,
        State::<2>::new(1.0, 0.0),
        t_end,
        &opts,
    );
    assert!(sol.status.is_ok());
    assert_eq!(sol.t, t_end);
    ((sol.y[0] - t_end.cos()).powi(2) + (sol.y[1] + t_end.sin()).powi(2)).sqrt()
}

fn measured_order(method: Method, h: f64) -> f64 {
    let e1 = global_error(method, h);
    let e2 = global_error(method, h / 2.0);
    (e1 / e2).log2()
}

#[test]
fn dormand_prince_is_fifth_order() {
    let p = measured_order(Method::Dp5, 0.1);
    assert!((p - 5.0).abs() < 0.2, "measured order {p}");
}

#[test]
fn classical_rk4_is_fourth_order() {
    let p = measured_order(Method::Rk4, 0.05);
    assert!((p - 4.0).abs() < 0.1, "measured order {p}");
}

#[test]
fn explicit_euler_is_first_order() {
    let p = measured_order(Method::Euler, 1e-3);
    assert!((p - 1.0).abs() < 0.02, "measured order {p}");
}

/// Records the dense output at the middle of the first step.
struct MidStep<S> {
    inner: S,
    mid: Option<State<2>>,
}

impl<S: OdeSystem<2>> OdeSystem<2> for MidStep<S> {
    fn rhs(&self, t: f64, y: &State<2>) -> State<2> {
        self.inner.rhs(t, y)
    }
    fn on_step(&mut self, step: &cushion_ode::Step<'_, 2>, _ctl: &mut cushion_ode::Control) {
        if self.mid.is_none() {
            self.mid = Some(step.at(0.5 * (step.t0 + step.t1)));
        }
    }
}

/// Local error of the dense output at the middle of one step of size h from the exact state.
fn dense_local_error(h: f64) -> f64 {
    let opts = SolverOptions {
        h0: Some(h),
        h_max: h,
        rtol: Tolerance::Scalar(1e10),
        atol: Tolerance::Scalar(1e10),
        ..Default::default()
    };
    let mut sys = MidStep {
        inner: Oscillator,
        mid: None,
    };
    solve(&mut sys, 0.0, State::<2>::new(1.0, 0.0), h, &opts);
    let m = sys.mid.unwrap();
    let t = 0.5 * h;
    ((m[0] - t.cos()).powi(2) + (m[1] + t.sin()).powi(2)).sqrt()
}

#[test]
fn dense_output_is_fourth_order() {
    // A continuous extension of order 4 has local error O(h^5): ratio 2^5 when h halves.
    let p_local = (dense_local_error(0.4) / dense_local_error(0.2)).log2();
    assert!((p_local - 5.0).abs() < 0.25, "local exponent {p_local}");
}

#[test]
fn tolerance_proportionality() {
    // Error falls steadily as the tolerance falls (DOPRI5: roughly tol^(5/6)).
    let err = |tol: f64| {
        let opts = SolverOptions {
            rtol: Tolerance::Scalar(tol),
            atol: Tolerance::Scalar(tol),
            ..Default::default()
        };
        let sol = solve(&mut Oscillator, 0.0, State::<2>::new(1.0, 0.0), 10.0, &opts);
        ((sol.y[0] - 10f64.cos()).powi(2) + (sol.y[1] + 10f64.sin()).powi(2)).sqrt()
    };
    let (e6, e9) = (err(1e-6), err(1e-9));
    let slope = (e6 / e9).log10() / 3.0;
    assert!(
        slope > 0.7 && slope < 1.1,
        "slope {slope}: e6 {e6:e}, e9 {e9:e}"
    );
    assert!(e9 < 1e-7);
}
