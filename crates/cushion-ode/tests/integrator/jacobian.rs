//! Finite-difference Jacobians and `df/dt` against analytic ones, and the implicit method with
//! either.

use cushion_ode::jacobian::{finite_difference_jacobian, finite_difference_time_derivative};
use cushion_ode::test_models::hires::{self, Hires};
use cushion_ode::test_models::manufactured::Manufactured;
use cushion_ode::test_models::orego::{self, Orego};
use cushion_ode::test_models::robertson::Robertson;
use cushion_ode::test_models::van_der_pol::VanDerPol;
use cushion_ode::{solve, Matrix, Method, OdeSystem, SolverOptions, State, Status, Tolerance};

/// Largest entry error, relative to the largest entry of its column (so that a zero entry next
/// to a large one is judged on the column's scale).
fn column_relative_error<const N: usize>(fd: &Matrix<N>, exact: &Matrix<N>) -> f64 {
    let mut worst: f64 = 0.0;
    for c in 0..N {
        let scale = exact.column(c).amax().max(f64::MIN_POSITIVE);
        worst = worst.max((fd.column(c) - exact.column(c)).amax() / scale);
    }
    worst
}

fn compare<S: OdeSystem<N>, const N: usize>(name: &str, sys: &S, y: &State<N>) -> f64 {
    let f0 = sys.rhs(0.0, y);
    let fd = finite_difference_jacobian(sys, 0.0, y, &f0);
    let exact = sys.jacobian(0.0, y).unwrap();
    let e = column_relative_error(&fd, &exact);
    println!("{name}: finite-difference Jacobian, largest column-relative error {e:.1e}");
    e
}

#[test]
fn finite_difference_jacobians_match_the_analytic_ones() {
    // Forward differences with increments delta = sqrt(eps max(1e-5, |y_j|)): truncation
    // error ~ delta |f''| / 2 and rounding error ~ eps |f| / delta, relative to the column's
    // scale |J|. The rounding term dominates where |f| is large beside |J| |y|: OREGO at
    // y1 = 1e4 (|f1| 2.4e5, column scale 18) is the worst here.
    let hires_mid = State::<8>::from([6e-4, 1.2e-4, 6e-5, 1.2e-3, 2.4e-3, 6e-3, 2.8e-3, 2.9e-3]);
    assert!(compare("HIRES y0", &Hires, &hires::initial_state()) < 1e-6);
    assert!(compare("HIRES", &Hires, &hires_mid) < 1e-6);
    assert!(compare("OREGO y0", &Orego, &orego::initial_state()) < 1e-6);
    assert!(compare("OREGO", &Orego, &State::<3>::new(1.0e4, 0.6, 2.0e3)) < 1e-5);
    assert!(compare("ROBER", &Robertson, &State::<3>::new(0.7, 3e-5, 0.3)) < 1e-6);
    assert!(compare("VDPOL", &VanDerPol { mu: 1e6 }, &State::<2>::new(1.7, -0.9)) < 1e-6);
}

#[test]
fn finite_difference_time_derivative_matches_the_analytic_one() {
    for t in [0.0, 0.3, 2.0, 100.0] {
        let y = State::<2>::new(0.4, -0.2);
        let f0 = Manufactured.rhs(t, &y);
        let fd = finite_difference_time_derivative(&Manufactured, t, &y, &f0);
        let exact = Manufactured.time_derivative(t, &y).unwrap();
        let e = (fd - exact).amax() / exact.amax();
        assert!(e < 1e-6, "t = {t}: {fd} vs {exact}");
    }
}

/// A system with its Jacobian hidden, so the integrator differentiates it itself.
struct NoJacobian<S>(S);

impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for NoJacobian<S> {
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.0.rhs(t, y)
    }
    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        self.0.time_derivative(t, y)
    }
}

#[test]
fn rodas_with_finite_differences_matches_rodas_with_the_jacobian() {
    let opts = SolverOptions {
        method: Method::Rodas,
        rtol: Tolerance::Scalar(1e-6),
        atol: Tolerance::Scalar(1e-10),
        ..Default::default()
    };
    let y0 = hires::initial_state();
    let exact = solve(&mut Hires, 0.0, y0, hires::T_END, &opts);
    let fd = solve(&mut NoJacobian(Hires), 0.0, y0, hires::T_END, &opts);
    assert_eq!(exact.status, Status::Success);
    assert_eq!(fd.status, Status::Success);
    // The same steps within a few, and the same answer well within the tolerance.
    let (a, b) = (exact.stats, fd.stats);
    assert!(a.steps.abs_diff(b.steps) <= 3, "{a:?} vs {b:?}");
    for i in 0..8 {
        let scale = 1e-10 + 1e-6 * hires::REFERENCE[i].abs();
        assert!((exact.y[i] - fd.y[i]).abs() < 0.1 * scale, "component {i}");
    }
    // Each finite-difference Jacobian costs N = 8 evaluations of f, counted in rhs_evals.
    let extra = b.rhs_evals - (5 * (b.steps + b.rejected) + (b.steps - 1) + 2);
    assert_eq!(extra, 8 * b.jacobian_evals);
    println!("HIRES with finite differences: {b:?}");
}
