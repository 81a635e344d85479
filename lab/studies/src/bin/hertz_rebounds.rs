//! A lone elastic Hertz rebound after a flight, over a grid of stiffness, speed and tolerance (a
//! benchmark of accuracy, not a test): `cargo run --release -p cushion-studies --bin
//! hertz_rebounds -- [dp5|dop853|rodas ...] [--undeclared]`.
//!
//! The body of `test_models::hertz_rebound` must leave the wall as fast as it hit it. It
//! declares the contact's end a kink of `f` ([`cushion_ode::OdeSystem::kinked_at_event`]);
//! `--undeclared` leaves that out, for the integrator as it was before it asked.
//!
//! Grid: `K/m` 1e5 to 1e9 N/m^1.5/kg, `v0` 1 to 100 cm/s, rtol 1e-5 to 1e-9 (atol rtol / 1000),
//! 125 cases a method. One line per case: `K/m v0 rtol error evaluations`, `error` the rebound
//! speed's relative error in units of rtol; then, per method, the largest error, the cases above
//! 20 rtol and the evaluations of the whole grid.

use cushion_ode::test_models::hertz_rebound::rebound;
use cushion_ode::Method;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let declares_kink = !args.iter().any(|a| a == "--undeclared");
    let mut methods: Vec<Method> = args
        .iter()
        .filter(|a| *a != "--undeclared")
        .map(|m| match m.as_str() {
            "dp5" => Method::Dp5,
            "dop853" => Method::Dop853,
            "rodas" => Method::Rodas,
            other => panic!("unknown argument {other}: dp5, dop853, rodas or --undeclared"),
        })
        .collect();
    if methods.is_empty() {
        methods = vec![Method::Dp5, Method::Dop853];
    }
    let stiffnesses = [1e5, 1e6, 1e7, 1e8, 1e9];
    let speeds = [0.01, 0.03, 0.1, 0.3, 1.0];
    let rtols = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    let mut totals = Vec::new();
    for &method in &methods {
        let (mut worst, mut above, mut evals, mut failed) = (0.0f64, 0, 0, 0);
        println!("{method:?}: K/m v0 rtol error/rtol evaluations");
        for &k in &stiffnesses {
            for &v0 in &speeds {
                for &rtol in &rtols {
                    match rebound(method, declares_kink, k, v0, rtol) {
                        Some((err, n)) => {
                            let e = err / rtol;
                            println!("{k:.0e} {v0} {rtol:.0e} {e:.2} {n}");
                            worst = worst.max(e);
                            above += usize::from(e > 20.0);
                            evals += n;
                        }
                        None => {
                            println!("{k:.0e} {v0} {rtol:.0e} no lift-off");
                            failed += 1;
                        }
                    }
                }
            }
        }
        totals.push((method, worst, above, evals, failed));
    }
    for (method, worst, above, evals, failed) in totals {
        println!(
            "{method:?}: largest {worst:.1} rtol, {above} cases above 20 rtol, {evals} evaluations, {failed} without a lift-off"
        );
    }
}
