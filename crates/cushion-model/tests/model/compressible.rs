//! The compressible-liquid model (`docs/model.md`, section "Compressible liquid"), solved by the
//! implicit method: the paper's scene runs to its end with a bounded number of evaluations, agrees
//! with the lumped model to about 1e-4 at oil's bulk modulus and converges to it as the bulk
//! modulus grows, and the orifice's laminar range (below its critical Reynolds number) changes the
//! impact by less than the tolerance.

use cushion_model::{simulate_with_ledger, RunOptions, RunStatus, Scene};

use crate::common;

use crate::common::run_ok as run;

fn paper_with(sets: &[(&str, &str)]) -> Scene {
    common::paper("paper-hydraulic-dt70", sets)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn the_paper_scene_with_a_compressible_liquid_is_solved_by_the_implicit_method() {
    let tol = [("solver.rtol", "1e-7"), ("solver.atol", "1e-10")];
    let lumped = run(&paper_with(&tol));
    let scene = paper_with(&[
        tol[0],
        tol[1],
        ("hydraulic.bulk_modulus", "1.5e9"),
        ("solver.method", "rodas"),
    ]);
    let (r, ledger) = simulate_with_ledger(&scene, &RunOptions::default());
    let rich = r.summary;
    assert_eq!(rich.status, RunStatus::Ok, "{}", rich.message);
    // DOPRI5 needs some 400 million evaluations here (measured: 56,353)
    assert!(rich.stats.rhs_evals < 100_000, "{}", rich.stats.rhs_evals);
    // the lumped model's accuracy against the richer one (measured: 8.2e-5, 2.4e-5, 7.6e-6,
    // 9e-7)
    let f = rel(rich.peak_robot_force, lumped.peak_robot_force);
    let s = rel(rich.max_stroke, lumped.max_stroke);
    let p = rel(
        rich.max_gas_pressure.unwrap(),
        lumped.max_gas_pressure.unwrap(),
    );
    let v = rel(
        rich.object_final_velocity.unwrap(),
        lumped.object_final_velocity.unwrap(),
    );
    assert!(
        f < 2e-4 && s < 1e-4 && p < 1e-4 && v < 1e-5,
        "{f:e} {s:e} {p:e} {v:e}"
    );
    assert_eq!(rich.object_impacts, lumped.object_impacts);
    // the ledger, with the liquid's compression energy, closes
    let residual = ledger.unwrap().residual;
    assert!(residual < 1e-6, "{residual:e}");
}

#[test]
fn the_orifices_laminar_range_changes_the_impact_by_less_than_the_tolerance() {
    let (rtol, atol) = (1e-6, 1e-9);
    let with = |re_cr: &str| {
        run(&paper_with(&[
            ("solver.rtol", "1e-6"),
            ("solver.atol", "1e-9"),
            ("hydraulic.bulk_modulus", "1.5e9"),
            ("solver.method", "rodas"),
            ("hydraulic.critical_reynolds", re_cr),
        ]))
    };
    let laminar = with("12");
    // a critical Reynolds number of 1e-9: turbulent down to 6e-21 Pa
    let turbulent = with("1e-9");
    let within = |a: f64, b: f64, floor: f64| (a - b).abs() <= 3.0 * (rtol * b.abs() + floor);
    assert!(within(
        laminar.peak_robot_force,
        turbulent.peak_robot_force,
        0.0
    ));
    assert!(within(
        laminar.object_final_velocity.unwrap(),
        turbulent.object_final_velocity.unwrap(),
        0.0
    ));
    assert!(within(laminar.max_stroke, turbulent.max_stroke, atol));
    assert!(within(
        laminar.max_gas_pressure.unwrap(),
        turbulent.max_gas_pressure.unwrap(),
        0.0
    ));
    // the impulse is a small net value: its error is measured on the momentum scale
    // (m_t + m_p) v_max, as in tests/model/tolerance.rs
    let momentum = (0.048 + 0.246) * 1.0;
    assert!(
        within(
            laminar.robot_impulse,
            turbulent.robot_impulse,
            rtol * momentum
        ),
        "{} vs {}",
        laminar.robot_impulse,
        turbulent.robot_impulse
    );
    // and it is what makes the liquid at rest cheap: the square-root law's infinite slope at
    // zero flow costs the implicit method about three times the evaluations (measured 22,067
    // against 62,842)
    assert!(
        2 * laminar.stats.rhs_evals < turbulent.stats.rhs_evals,
        "{} vs {}",
        laminar.stats.rhs_evals,
        turbulent.stats.rhs_evals
    );
}

#[test]
fn the_compressible_model_converges_to_the_lumped_one_as_the_bulk_modulus_grows() {
    let tol = [("solver.rtol", "1e-8"), ("solver.atol", "1e-11")];
    let lumped = run(&paper_with(&tol));
    let mut last = f64::INFINITY;
    // measured: 1.26e-3, 1.22e-4, 1.23e-5 (the liquid's compliance falls as 1 / beta)
    for beta in ["1e8", "1e9", "1e10"] {
        let rich = run(&paper_with(&[
            tol[0],
            tol[1],
            ("hydraulic.bulk_modulus", beta),
            ("solver.method", "rodas"),
        ]));
        let f = rel(rich.peak_robot_force, lumped.peak_robot_force);
        assert!(f < last / 5.0, "beta {beta}: {f:e} after {last:e}");
        last = f;
    }
    assert!(last < 2e-5, "{last:e}");
}
