//! Integrator benchmark (not a test): `cargo bench -p cushion-ode --bench step_cost`.
//!
//! 1. Arenstorf orbit over one period at tolerances 1e-4 .. 1e-12, under DOPRI5 and DOP853:
//!    steps, rejections, right-hand-side evaluations and end error (compare with
//!    `lab/arenstorf_dopri5.py`, Hairer's DOPRI5 through SciPy; `python -m lab.arenstorf`
//!    records the table for docs/integrator.md).
//! 2. The integrator's own cost per step, beyond the right-hand-side evaluations: total time
//!    minus `rhs_evals` times the measured cost of one evaluation, over attempted steps.

use std::hint::black_box;
use std::time::Instant;

use cushion_ode::test_models::arenstorf::{initial_state, Arenstorf, PERIOD};
use cushion_ode::test_models::exponential::Oscillator;
use cushion_ode::{solve, Method, OdeSystem, SolverOptions, State, StiffnessAction, Tolerance};

fn opts(tol: f64) -> SolverOptions {
    SolverOptions {
        method: Method::Dp5,
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        stiffness: StiffnessAction::Warn,
        max_steps: 10_000_000,
        ..Default::default()
    }
}

/// Median seconds per call of `f` over `reps` batches of `inner` calls.
fn time_per_call(reps: usize, inner: usize, mut f: impl FnMut()) -> f64 {
    let mut samples = Vec::with_capacity(reps);
    for _ in 0..reps {
        let t = Instant::now();
        for _ in 0..inner {
            f();
        }
        samples.push(t.elapsed().as_secs_f64() / inner as f64);
    }
    samples.sort_by(|a, b| a.total_cmp(b));
    samples[reps / 2]
}

fn rhs_cost<S: OdeSystem<N>, const N: usize>(sys: &S, y: State<N>) -> f64 {
    let n = 100_000;
    time_per_call(15, 1, || {
        for i in 0..n {
            black_box(sys.rhs(black_box(i as f64), black_box(&y)));
        }
    }) / n as f64
}

fn overhead<S: OdeSystem<N>, const N: usize>(
    name: &str,
    sys: &mut S,
    y0: State<N>,
    t_end: f64,
    tol: f64,
) {
    let o = opts(tol);
    let sol = solve(sys, 0.0, y0, t_end, &o);
    let per_solve = time_per_call(21, 20, || {
        black_box(solve(sys, 0.0, black_box(y0), t_end, &o));
    });
    let per_rhs = rhs_cost(sys, y0);
    let steps = (sol.stats.steps + sol.stats.rejected) as f64;
    let beyond = (per_solve - sol.stats.rhs_evals as f64 * per_rhs) / steps;
    println!(
        "{name:<11} N={N} tol={tol:.0e}: {} steps, {} rhs evals, {:.1} us/solve, {:.1} ns/step, rhs {:.1} ns/eval, integrator {:.1} ns/step beyond rhs",
        sol.stats.steps,
        sol.stats.rhs_evals,
        per_solve * 1e6,
        per_solve / steps * 1e9,
        per_rhs * 1e9,
        beyond * 1e9
    );
}

fn main() {
    println!("# Arenstorf orbit, one period, rtol = atol = tol");
    println!(
        "{:>7} {:>8} {:>8} {:>9} {:>10} {:>12} {:>10}",
        "method", "tol", "steps", "rejected", "rhs_evals", "end_error", "us/solve"
    );
    for (name, method) in [("dp5", Method::Dp5), ("dop853", Method::Dop853)] {
        for k in 4..=12 {
            let tol = 10f64.powi(-k);
            let o = SolverOptions {
                method,
                ..opts(tol)
            };
            let sol = solve(&mut Arenstorf, 0.0, initial_state(), PERIOD, &o);
            let err = (sol.y - initial_state()).amax();
            let t = time_per_call(11, 5, || {
                black_box(solve(
                    &mut Arenstorf,
                    0.0,
                    black_box(initial_state()),
                    PERIOD,
                    &o,
                ));
            });
            println!(
                "{:>7} {:>8.0e} {:>8} {:>9} {:>10} {:>12.3e} {:>10.1}",
                name,
                tol,
                sol.stats.steps,
                sol.stats.rejected,
                sol.stats.rhs_evals,
                err,
                t * 1e6
            );
        }
    }
    println!();
    println!("# Cost per step beyond the right-hand side");
    overhead(
        "oscillator",
        &mut Oscillator,
        State::<2>::new(1.0, 0.0),
        100.0,
        1e-8,
    );
    overhead("arenstorf", &mut Arenstorf, initial_state(), PERIOD, 1e-8);
}
