//! `solver.method = "auto"` on the scenes: DOPRI5 where a scene is not stiff (every paper
//! scene, to the bit), Rodas where it is (a tool held on its stop by a small orifice, the
//! compressible liquid), and the steel stops and contacts users will try. The references are
//! DOPRI5 runs at tight tolerances.

use cushion_model::{simulate, RunOptions, RunStatus, Summary};

use crate::common::{kept_scene, paper, run_ok as run};

/// The largest difference of the results a user reads, each over its own scale: speeds over
/// the approach speed, forces over the peak force, the stroke over the stroke's scale.
fn difference(a: &Summary, b: &Summary) -> f64 {
    let v = (a.object_final_velocity.unwrap() - b.object_final_velocity.unwrap()).abs();
    let f = (a.peak_robot_force - b.peak_robot_force).abs() / b.peak_robot_force.abs();
    let s = (a.max_stroke - b.max_stroke).abs() / 0.023;
    v.max(f).max(s)
}

#[test]
fn auto_is_dopri5_to_the_bit_on_every_paper_scene() {
    for name in [
        "paper-hydraulic-dt70",
        "paper-hydraulic-dt10",
        "paper-bistable-dt70",
        "paper-bistable-dt10",
        "paper-rigid",
    ] {
        let dp5 = run(&paper(name, &[("solver.method", "dp5")]));
        let auto = run(&paper(name, &[("solver.method", "auto")]));
        assert_eq!(auto, dp5, "{name}");
        assert_eq!(auto.stats.method_switches, 0);
    }
}

#[test]
fn a_small_orifice_that_overdamps_the_tool_switches_to_rodas_and_saves_work() {
    // A point of sweeps/design-space.toml with a 2 mm orifice: the orifice's damping,
    // d(dp A_p)/d(sd) = c0 rho_L (A_p/A_o)^2 |sd| A_p, (A_p/A_o)^2 = 1e4 here, makes the tool's
    // motion relative to the flange a fast overdamped mode (|lambda| ~ 7e5 |sd| 1/s), which
    // holds DOPRI5 at its stability limit (its test fires); Rodas steps over it.
    let sets = [
        ("robot.dead_time", "0.0202"),
        ("hydraulic.gas_pressure", "536.171377"),
        ("hydraulic.orifice_radius", "0.002023"),
        ("object.mass", "0.979947"),
    ];
    let with = |extra: &[(&'static str, &'static str)]| {
        let mut all = sets.to_vec();
        all.extend_from_slice(extra);
        run(&paper("paper-hydraulic-dt70", &all))
    };
    let dp5 = with(&[("solver.method", "dp5")]);
    let auto = with(&[("solver.method", "auto")]);
    let reference = with(&[
        ("solver.method", "dp5"),
        ("solver.rtol", "1e-11"),
        ("solver.atol", "1e-14"),
    ]);
    println!(
        "dp5 {:?}\nauto {:?}\nerrors: dp5 {:.2e}, auto {:.2e}",
        dp5.stats,
        auto.stats,
        difference(&dp5, &reference),
        difference(&auto, &reference)
    );
    assert!(dp5.stats.stiff);
    assert!(auto.stats.method_switches >= 1 && auto.stats.jacobians > 0);
    // measured: 1,085 evaluations against DOPRI5's 3,070
    assert!(
        auto.stats.rhs_evals * 2 < dp5.stats.rhs_evals,
        "{:?}",
        auto.stats
    );
    // as accurate as DOPRI5 at the same tolerance (rtol 1e-6): within 30 rtol of the reference
    assert!(difference(&auto, &reference) < 3e-5);
    assert_eq!(auto.object_impacts, reference.object_impacts);
}

#[test]
fn steel_stops_and_a_steel_contact_are_solved_with_no_more_work_than_dopri5() {
    // End-stops at 1e11 N/m^1.5 and a tool-object contact at 1e10: the tool rings on its stop
    // with little damping, so accuracy, not stability, bounds the step: auto stays with
    // DOPRI5 (or leaves it only where Rodas is cheaper).
    for sets in [
        vec![("stops.stiffness", "1e11")],
        vec![("object.contact_stiffness", "1e10")],
        vec![
            ("stops.stiffness", "1e11"),
            ("object.contact_stiffness", "1e10"),
        ],
    ] {
        let scene = |extra: &[(&'static str, &'static str)]| {
            let mut all = sets.clone();
            all.extend_from_slice(extra);
            paper("paper-hydraulic-dt70", &all)
        };
        let dp5 = run(&scene(&[("solver.method", "dp5")]));
        let auto = run(&scene(&[("solver.method", "auto")]));
        let reference = run(&scene(&[
            ("solver.method", "dp5"),
            ("solver.rtol", "1e-10"),
            ("solver.atol", "1e-13"),
        ]));
        let tight = run(&scene(&[
            ("solver.method", "auto"),
            ("solver.rtol", "1e-10"),
            ("solver.atol", "1e-13"),
        ]));
        println!(
            "{sets:?}: dp5 {} evaluations, auto {} ({} switches); error {:.2e}, at rtol 1e-10 {:.2e}",
            dp5.stats.rhs_evals,
            auto.stats.rhs_evals,
            auto.stats.method_switches,
            difference(&auto, &reference),
            difference(&tight, &reference)
        );
        // within 3 %: DOPRI5 alone carries the first step it learned after each recurring event
        // to the next one (`cushion-ode/src/restart_steps.rs`), and `auto` forgets those at
        // every switch (steel contact: dp5 7,684 evaluations, auto 7,850 with 6 switches, 28
        // evaluations a switch; with both steel parts 25,985 and 26,116)
        assert!(
            auto.stats.rhs_evals as f64 <= 1.03 * dp5.stats.rhs_evals as f64,
            "{sets:?}"
        );
        // as accurate as DOPRI5 at the same tolerance (the peak force of the steel stops
        // comes from one of about 150 bounces on the stop: 5e-5 apart at rtol 1e-6 under both)
        let own = difference(&dp5, &reference).max(1e-6);
        assert!(difference(&auto, &reference) <= 1.5 * own, "{sets:?}");
        // and agrees with DOPRI5 at tight tolerance
        assert!(difference(&tight, &reference) < 1e-7, "{sets:?}");
    }
}

#[test]
fn the_compressible_liquid_is_solved_by_auto_within_its_evaluation_bound() {
    let tol = [("solver.rtol", "1e-7"), ("solver.atol", "1e-10")];
    let lumped = run(&paper("paper-hydraulic-dt70", &tol));
    let r = simulate(
        &paper(
            "paper-hydraulic-dt70",
            &[
                tol[0],
                tol[1],
                ("hydraulic.bulk_modulus", "1.5e9"),
                ("solver.method", "auto"),
            ],
        ),
        &RunOptions::default(),
    );
    let rich = r.summary;
    assert_eq!(rich.status, RunStatus::Ok, "{}", rich.message);
    println!("{:?}", rich.stats);
    // DOPRI5 would need about 4e8 evaluations; measured 12,027 (one switch, at about 1 ms)
    assert!(rich.stats.rhs_evals < 100_000, "{:?}", rich.stats);
    assert!(rich.stats.method_switches >= 1);
    assert!(r.events.iter().any(|e| e.name == "switch_to_rodas"));
    // the lumped model's own accuracy against the compressible one at oil's bulk modulus
    // (docs/model.md: 8.2e-5 on the peak force)
    let f = (rich.peak_robot_force - lumped.peak_robot_force).abs() / lumped.peak_robot_force.abs();
    assert!(f < 2e-4, "peak force {f:e}");
}

#[test]
fn a_compressible_liquid_held_under_the_stability_limit_switches() {
    // A wide corner scene (`wide_scenes 20000 1130 4917 --corners`): oil at 6.7e8 Pa behind a
    // 10 mm orifice whose laminar range ends at 0.076 Pa, four times the tolerance on p_m. The
    // orifice's rate beta dQ/ddp / V_m, about 1.2e9 /s, holds DOPRI5's controller at
    // h |lambda| 1.6-1.7, half its stability boundary and under the quick switch's threshold,
    // for a million steps (43 % of t_end); the patient switch (`cushion-ode/src/auto.rs`,
    // `PATIENT_STEPS`) hands it to Rodas after a thousand.
    let scene = kept_scene("wide-1130-corner-4917", &[("solver.method", "auto")]);
    let auto = run(&scene);
    let reference = run(&kept_scene(
        "wide-1130-corner-4917",
        &[
            ("solver.method", "rodas"),
            ("solver.rtol", "1e-10"),
            ("solver.atol", "1e-13"),
        ],
    ));
    println!("auto {:?}", auto.stats);
    assert_eq!(auto.stats.method_switches, 1);
    // measured: 6,648 evaluations (1,000 DOPRI5 steps, then 95 of Rodas)
    assert!(auto.stats.rhs_evals < 20_000, "{:?}", auto.stats);
    // the robot's peak force and impulse within the tolerance asked for (rtol 1.1e-6)
    let rtol = scene.solver.rtol;
    let f = (auto.peak_robot_force - reference.peak_robot_force).abs()
        / reference.peak_robot_force.abs();
    let j = (auto.robot_impulse - reference.robot_impulse).abs() / reference.robot_impulse.abs();
    assert!(
        f < 10.0 * rtol && j < 10.0 * rtol,
        "force {f:e}, impulse {j:e}"
    );
}

#[test]
fn the_compressible_liquid_at_a_loose_tolerance_switches_early() {
    // At rtol 1e-4 the paper scene with a stiff liquid (1e10 Pa) held DOPRI5 under the quick
    // switch's threshold for 543,000 steps (3.27 M evaluations) before it switched; the
    // patient switch does so after a thousand (8,556 evaluations in all)
    let scene = |method| {
        paper(
            "paper-hydraulic-dt70",
            &[
                ("hydraulic.bulk_modulus", "1e10"),
                ("solver.rtol", "1e-4"),
                ("solver.atol", "1e-7"),
                ("solver.method", method),
            ],
        )
    };
    let auto = run(&scene("auto"));
    let rodas = run(&scene("rodas"));
    println!("auto {:?}\nrodas {:?}", auto.stats, rodas.stats);
    assert!(auto.stats.rhs_evals < 30_000, "{:?}", auto.stats);
    assert!(difference(&auto, &rodas) < 1e-4);
}
