//! Work and wall time of the implicit method on the classic stiff problems (a benchmark, not a
//! test): `cargo run --release -p cushion-studies --bin stiff_ode` (or `python -m lab.stiff_ode`,
//! which also runs SciPy's solvers on the same problems and records both).
//!
//! For each problem, Rodas4 with the system's Jacobian, Rodas4 with finite differences, and
//! DOPRI5 (stopped after 2,000,000 steps where stiffness makes it hopeless): steps, rejected
//! steps, evaluations of f (those of finite-difference Jacobians included), Jacobians, LU
//! factorizations, the mixed error `max |y_i - ref_i| / (atol_i + rtol |ref_i|)` at the end
//! against the published reference, and the median wall time of repeated runs.

use std::time::Instant;

use cushion_ode::test_models::hires::{self, Hires};
use cushion_ode::test_models::orego::{self, Orego};
use cushion_ode::test_models::robertson::{self, Robertson};
use cushion_ode::test_models::van_der_pol::{VanDerPol, REFERENCE_EPS_1E6};

use cushion_studies::timing::wall_time;

use cushion_ode::{
    solve, Method, OdeSystem, Solution, SolverOptions, State, StiffnessAction, Tolerance,
};

/// The system with its Jacobian hidden: the integrator differentiates it itself.
struct NoJacobian<'a, S>(&'a S);

impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for NoJacobian<'_, S> {
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.0.rhs(t, y)
    }
    fn time_derivative(&self, t: f64, y: &State<N>) -> Option<State<N>> {
        self.0.time_derivative(t, y)
    }
}

struct Problem<'a, S, const N: usize> {
    name: &'a str,
    sys: S,
    y0: State<N>,
    t_end: f64,
    rtol: f64,
    atol: [f64; N],
    reference: [f64; N],
}

fn print_row<const N: usize>(
    name: &str,
    method: &str,
    sol: &Solution<N>,
    p_ref: &[f64; N],
    rtol: f64,
    atol: &[f64; N],
    wall: f64,
) {
    let s = &sol.stats;
    let err = if sol.status.is_ok() {
        let e = (0..N)
            .map(|i| (sol.y[i] - p_ref[i]).abs() / (atol[i] + rtol * p_ref[i].abs()))
            .fold(0.0, f64::max);
        format!("{e:9.2}")
    } else {
        format!("{:>9}", format!("{:?}", sol.status))
    };
    println!(
        "{name:14} {method:10} {:>8} {:>6} {:>9} {:>6} {:>6} {err} {:>10.3}",
        s.steps,
        s.rejected,
        s.rhs_evals,
        s.jacobian_evals,
        s.lu_decompositions,
        wall * 1e3
    );
}

fn run<S: OdeSystem<N>, const N: usize>(p: Problem<'_, S, N>) {
    let opts = |method: Method| SolverOptions {
        method,
        rtol: Tolerance::Scalar(p.rtol),
        atol: Tolerance::PerComponent(p.atol.to_vec()),
        stiffness: StiffnessAction::Off,
        max_steps: 2_000_000,
        ..Default::default()
    };
    let mut sys = p.sys;
    let rodas = opts(Method::Rodas);
    let sol = solve(&mut sys, 0.0, p.y0, p.t_end, &rodas);
    let wall = wall_time(0.3, || solve(&mut sys, 0.0, p.y0, p.t_end, &rodas).y).0;
    print_row(p.name, "rodas", &sol, &p.reference, p.rtol, &p.atol, wall);

    let mut fd = NoJacobian(&sys);
    let sol = solve(&mut fd, 0.0, p.y0, p.t_end, &rodas);
    let wall = wall_time(0.3, || solve(&mut fd, 0.0, p.y0, p.t_end, &rodas).y).0;
    print_row(
        p.name,
        "rodas (FD)",
        &sol,
        &p.reference,
        p.rtol,
        &p.atol,
        wall,
    );

    let dp5 = opts(Method::Dp5);
    let sol = solve(&mut sys, 0.0, p.y0, p.t_end, &dp5);
    let t = Instant::now();
    solve(&mut sys, 0.0, p.y0, p.t_end, &dp5);
    let wall = t.elapsed().as_secs_f64();
    print_row(p.name, "dp5", &sol, &p.reference, p.rtol, &p.atol, wall);
}

fn main() {
    println!(
        "{:14} {:10} {:>8} {:>6} {:>9} {:>6} {:>6} {:>9} {:>10}",
        "problem", "method", "steps", "rej", "rhs_evals", "jacs", "LUs", "mixed err", "wall ms"
    );
    run(Problem {
        name: "VDPOL mu=1e6",
        sys: VanDerPol { mu: 1e6 },
        y0: State::<2>::new(2.0, 0.0),
        t_end: 2.0,
        rtol: 1e-6,
        atol: [1e-6; 2],
        reference: REFERENCE_EPS_1E6,
    });
    run(Problem {
        name: "ROBER",
        sys: Robertson,
        y0: State::<3>::new(1.0, 0.0, 0.0),
        t_end: robertson::T_END,
        rtol: 1e-6,
        atol: [1e-10, 1e-16, 1e-10],
        reference: robertson::REFERENCE_1E11,
    });
    run(Problem {
        name: "HIRES",
        sys: Hires,
        y0: hires::initial_state(),
        t_end: hires::T_END,
        rtol: 1e-6,
        atol: [1e-10; 8],
        reference: hires::REFERENCE,
    });
    run(Problem {
        name: "OREGO",
        sys: Orego,
        y0: orego::initial_state(),
        t_end: orego::T_END,
        rtol: 1e-6,
        atol: [1e-8; 3],
        reference: orego::REFERENCE,
    });
}
