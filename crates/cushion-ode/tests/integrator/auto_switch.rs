//! `Method::Auto`: DOPRI5 while a problem is not stiff, Rodas while it is (`auto.rs`). Checked
//! against closed forms and the test set's reference, with the work compared to each method
//! alone.

use cushion_ode::test_models::arenstorf::{self, Arenstorf};
use cushion_ode::test_models::fading_stiffness::FadingStiffness;
use cushion_ode::test_models::robertson::Robertson;
use cushion_ode::test_models::van_der_pol::VanDerPol;
use cushion_ode::{
    solve, Control, Direction, EventAction, Method, OdeSystem, SolverOptions, State, Status,
    StiffnessAction, Tolerance,
};

fn opts(method: Method, rtol: f64, atol: f64) -> SolverOptions {
    SolverOptions {
        method,
        rtol: Tolerance::Scalar(rtol),
        atol: Tolerance::Scalar(atol),
        stiffness: StiffnessAction::Off,
        max_steps: 10_000_000,
        ..Default::default()
    }
}

/// The problem with the switches it reports to the system.
struct Logged<S> {
    inner: S,
    switches: Vec<(f64, Method)>,
}

impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for Logged<S> {
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.inner.rhs(t, y)
    }
    fn jacobian(&self, t: f64, y: &State<N>) -> Option<cushion_ode::Matrix<N>> {
        self.inner.jacobian(t, y)
    }
    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        self.inner.time_derivative(t, y)
    }
    fn on_switch(&mut self, t: f64, _y: &State<N>, to: Method) {
        self.switches.push((t, to));
    }
}

#[test]
fn fading_stiffness_switches_to_rodas_and_back_and_meets_the_closed_form() {
    // lambda = 1e4 e^{-10 t}: stiff for DOPRI5 while lambda h > 3.3 at the accuracy's h, i.e.
    // until lambda falls to a few tens, near t = 0.6; the solution is sin t throughout.
    let problem = FadingStiffness {
        lambda0: 1e4,
        decay: 10.0,
    };
    let mut sys = Logged {
        inner: problem,
        switches: Vec::new(),
    };
    let (rtol, atol) = (1e-6, 1e-9);
    let y0 = State::<1>::zeros();
    let auto = solve(&mut sys, 0.0, y0, 3.0, &opts(Method::Auto, rtol, atol));
    assert_eq!(auto.status, Status::Success, "{}", auto.message);
    let err = (auto.y[0] - FadingStiffness::exact(3.0)[0]).abs();
    assert!(err < 10.0 * (atol + rtol * 3f64.sin().abs()), "error {err}");
    // one switch each way, in that order, the second after the stiffness has faded
    let to: Vec<Method> = sys.switches.iter().map(|s| s.1).collect();
    assert_eq!(to, [Method::Rodas, Method::Dp5], "{:?}", sys.switches);
    assert!(sys.switches[0].0 < 0.1, "{:?}", sys.switches);
    assert!(
        sys.switches[1].0 > 0.3 && sys.switches[1].0 < 1.5,
        "{:?}",
        sys.switches
    );
    assert_eq!(auto.stats.method_switches, 2);
    assert!(auto.stats.stiff);
    assert!(auto.stats.jacobian_evals > 0);

    // cheaper than either method alone: DOPRI5 pays for its stability limit while lambda is
    // large, Rodas for its Jacobians and factorizations while it is not
    let alone = |m| {
        let mut p = FadingStiffness {
            lambda0: 1e4,
            decay: 10.0,
        };
        solve(&mut p, 0.0, y0, 3.0, &opts(m, rtol, atol)).stats
    };
    let (dp5, rodas) = (alone(Method::Dp5), alone(Method::Rodas));
    println!(
        "auto {:?}\ndp5 rhs_evals {}\nrodas rhs_evals {} jacobians {}",
        auto.stats, dp5.rhs_evals, rodas.rhs_evals, rodas.jacobian_evals
    );
    // measured: 440 evaluations and 45 Jacobians; DOPRI5 2,072; Rodas 541 and 90 Jacobians
    assert!(auto.stats.rhs_evals < dp5.rhs_evals / 2);
    assert!(auto.stats.jacobian_evals < rodas.jacobian_evals);
}

#[test]
fn a_problem_that_is_never_stiff_is_dopri5_to_the_bit() {
    let y0 = arenstorf::initial_state();
    let t_end = arenstorf::PERIOD;
    let auto = solve(
        &mut Arenstorf,
        0.0,
        y0,
        t_end,
        &opts(Method::Auto, 1e-9, 1e-9),
    );
    let dp5 = solve(
        &mut Arenstorf,
        0.0,
        y0,
        t_end,
        &opts(Method::Dp5, 1e-9, 1e-9),
    );
    assert_eq!(auto.status, Status::Success);
    assert_eq!(auto.y, dp5.y);
    assert_eq!(auto.stats, dp5.stats);
    assert_eq!(auto.stats.method_switches, 0);
}

#[test]
fn van_der_pol_mu_1e3_costs_less_than_either_method_alone() {
    // Slow stiff stretches and fast jumps: Rodas on the former, DOPRI5 may take the latter.
    let y0 = State::<2>::new(2.0, -0.66);
    let reference = solve(
        &mut VanDerPol { mu: 1e3 },
        0.0,
        y0,
        2.0,
        &opts(Method::Dp5, 1e-13, 1e-13),
    );
    let (rtol, atol) = (1e-6, 1e-6);
    let run = |m| {
        solve(
            &mut VanDerPol { mu: 1e3 },
            0.0,
            y0,
            2.0,
            &opts(m, rtol, atol),
        )
    };
    let (auto, dp5, rodas) = (run(Method::Auto), run(Method::Dp5), run(Method::Rodas));
    assert_eq!(auto.status, Status::Success, "{}", auto.message);
    let mixed = (0..2)
        .map(|i| (auto.y[i] - reference.y[i]).abs() / (atol + rtol * reference.y[i].abs()))
        .fold(0.0, f64::max);
    println!(
        "auto {:?}; mixed error {mixed:.2}\ndp5 {} rhs_evals, rodas {}",
        auto.stats, dp5.stats.rhs_evals, rodas.stats.rhs_evals
    );
    assert!(mixed < 10.0, "mixed error {mixed}");
    assert!(auto.stats.method_switches >= 1);
    // measured: 2,518 evaluations against DOPRI5's 8,666 and Rodas's 3,632
    assert!(auto.stats.rhs_evals < dp5.stats.rhs_evals);
    assert!(auto.stats.rhs_evals < rodas.stats.rhs_evals);
}

#[test]
fn robertson_is_solved_where_dopri5_alone_runs_out_of_steps() {
    let rtol = 1e-6;
    let atol = vec![1e-10, 1e-16, 1e-10];
    let t_end = 1e5;
    let o = |m| SolverOptions {
        atol: Tolerance::PerComponent(atol.clone()),
        max_steps: 200_000,
        ..opts(m, rtol, 1.0)
    };
    let y0 = State::<3>::new(1.0, 0.0, 0.0);
    let auto = solve(&mut Robertson, 0.0, y0, t_end, &o(Method::Auto));
    let dp5 = solve(&mut Robertson, 0.0, y0, t_end, &o(Method::Dp5));
    assert_eq!(auto.status, Status::Success, "{}", auto.message);
    assert_eq!(dp5.status, Status::MaxSteps);
    // Robertson's y1 + y2 + y3 = 1 holds for any consistent method, to rounding
    assert!((auto.y.sum() - 1.0).abs() < 1e-12);
    // the reference at 1e5 from the same problem under Rodas at a tighter tolerance
    let tight = solve(
        &mut Robertson,
        0.0,
        y0,
        t_end,
        &SolverOptions {
            atol: Tolerance::PerComponent(vec![1e-14, 1e-20, 1e-14]),
            ..opts(Method::Rodas, 1e-10, 1.0)
        },
    );
    for (i, a) in atol.iter().enumerate() {
        let e = (auto.y[i] - tight.y[i]).abs() / (a + rtol * tight.y[i].abs());
        assert!(e < 10.0, "component {i}: mixed error {e}");
    }
}

/// A stiff decay towards a moving target with a crossing: `y' = -1e4 (y - t)`, event
/// `y = 0.5`. The crossing falls inside a Rodas step; its time is `0.5 + 1e-4` to within the
/// transient's `e^{-1e4 t}`.
struct StiffCrossing;

impl OdeSystem<1> for StiffCrossing {
    fn rhs(&self, t: f64, y: &State<1>) -> State<1> {
        State::<1>::new(-1e4 * (y[0] - t))
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<1>, g: &mut [f64]) {
        g[0] = y[0] - 0.5;
    }
    fn event_direction(&self, _i: usize) -> Direction {
        Direction::Rising
    }
    fn on_event(&mut self, _i: usize, _t: f64, _y: &mut State<1>, _c: &mut Control) -> EventAction {
        EventAction::Stop
    }
}

#[test]
fn events_inside_implicit_steps_are_located_on_their_dense_output() {
    // y = t - 1e-4 (1 - e^{-1e4 t}) exactly, so y = 0.5 at t = 0.5 + 1e-4 (e^{-5e3} is 0).
    let sol = solve(
        &mut StiffCrossing,
        0.0,
        State::<1>::zeros(),
        1.0,
        &opts(Method::Auto, 1e-8, 1e-10),
    );
    assert_eq!(sol.status, Status::StoppedByEvent);
    assert_eq!(sol.stats.method_switches, 1);
    let t = sol.events[0].t;
    assert!((t - 0.5001).abs() < 1e-9, "crossing at {t}");
}
