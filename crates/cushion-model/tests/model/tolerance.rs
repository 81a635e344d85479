//! The summary converges with the tolerance: on each paper scene the values a designer reads
//! (the object's final speed, the peak robot force, the robot impulse, the detection time) stay
//! within a small multiple of `rtol` of the same scene at rtol 1e-12, at every tolerance from
//! 1e-4 to 1e-8, fall by at least a factor of 100 from rtol 1e-4 to 1e-8, and the impact counts
//! never change. `python3 -m lab.scene_tolerances` records the same errors for rtol 1e-3 to 1e-10.

use cushion_model::{simulate, RunOptions, RunStatus, Scene, Summary};

fn paper(name: &str) -> Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../sweeps/scenes/{name}.toml"));
    Scene::from_file(&p).unwrap()
}

/// The summary at `rtol`, with atol = rtol / 1000 (the paper scenes' ratio).
fn at(scene: &Scene, rtol: f64) -> Summary {
    let mut s = scene.clone();
    s.set_from_str("solver.rtol", &rtol.to_string()).unwrap();
    s.set_from_str("solver.atol", &(rtol * 1e-3).to_string())
        .unwrap();
    let r = simulate(&s, &RunOptions::default()).summary;
    assert_eq!(r.status, RunStatus::Ok, "rtol {rtol}: {}", r.message);
    r
}

/// The errors against the reference, each in units of its own scale: the object's final speed
/// over the approach speed, the peak robot force relative, the robot impulse over the momentum
/// scale `(m_t + m_p) v_max`, the detection time over the run's length.
fn errors(scene: &Scene, s: &Summary, reference: &Summary) -> [f64; 4] {
    let v_max = scene.robot.approach_speed;
    let momentum = (scene.tool.mass + scene.object.mass) * v_max;
    let speed = s.object_final_velocity.unwrap() - reference.object_final_velocity.unwrap();
    let force = (s.peak_robot_force - reference.peak_robot_force) / reference.peak_robot_force;
    let impulse = s.robot_impulse - reference.robot_impulse;
    let detect = s.t_detect.unwrap() - reference.t_detect.unwrap();
    [
        speed.abs() / v_max,
        force.abs(),
        impulse.abs() / momentum,
        detect.abs() / scene.t_end,
    ]
}

const NAMES: [&str; 4] = [
    "object final speed",
    "peak robot force",
    "robot impulse",
    "detection time",
];

fn converges(name: &str) {
    let scene = paper(name);
    let reference = at(&scene, 1e-12);
    let counts = |s: &Summary| {
        (
            s.object_impacts,
            s.forward_stop_impacts,
            s.back_stop_impacts,
        )
    };
    let mut by_rtol = Vec::new();
    for rtol in [1e-4, 1e-6, 1e-8] {
        let s = at(&scene, rtol);
        assert_eq!(
            counts(&s),
            counts(&reference),
            "{name}, rtol {rtol}: impacts"
        );
        let e = errors(&scene, &s, &reference);
        for (k, err) in e.iter().enumerate() {
            // the errors are about 10 rtol at most (`python3 -m lab.scene_tolerances` records
            // them): 30 rtol leaves a margin, yet fails an error that stops following rtol
            assert!(
                *err <= 30.0 * rtol,
                "{name}, rtol {rtol}: {} error {err:.2e} > 30 rtol",
                NAMES[k]
            );
        }
        by_rtol.push(e);
    }
    for k in 0..4 {
        let (loose, tight) = (by_rtol[0][k], by_rtol[2][k]);
        // the detection time is already exact to ~1e-9 of the run at rtol 1e-4
        if k == 3 && loose <= 1e-8 {
            continue;
        }
        assert!(
            tight <= loose / 100.0,
            "{name}: {} error {tight:.2e} at rtol 1e-8 against {loose:.2e} at 1e-4",
            NAMES[k]
        );
    }
}

#[test]
fn hydraulic_converges_with_the_tolerance() {
    converges("paper-hydraulic-dt70");
}

#[test]
fn bistable_converges_with_the_tolerance() {
    converges("paper-bistable-dt70");
}

#[test]
fn rigid_converges_with_the_tolerance() {
    converges("paper-rigid");
}

/// The implicit method gives the same summary as DOPRI5 within the tolerance: on every paper
/// scene, `rodas` at rtol 1e-6 has the same impact counts as the rtol 1e-12 reference (a DOPRI5
/// run) and its four values lie within 30 rtol of it (measured: within 0.5 rtol; DOPRI5 at
/// 1e-6 is within 7.2).
#[test]
fn the_implicit_method_agrees_with_the_reference_on_every_paper_scene() {
    let rtol = 1e-6;
    for name in [
        "paper-hydraulic-dt70",
        "paper-hydraulic-dt10",
        "paper-bistable-dt70",
        "paper-bistable-dt10",
        "paper-rigid",
    ] {
        let scene = paper(name);
        let reference = at(&scene, 1e-12);
        let mut implicit = scene.clone();
        implicit.set_from_str("solver.method", "rodas").unwrap();
        let s = at(&implicit, rtol);
        assert_eq!(
            (
                s.object_impacts,
                s.forward_stop_impacts,
                s.back_stop_impacts
            ),
            (
                reference.object_impacts,
                reference.forward_stop_impacts,
                reference.back_stop_impacts
            ),
            "{name}: impact counts"
        );
        for (err, what) in errors(&scene, &s, &reference).iter().zip(NAMES) {
            assert!(
                *err <= 30.0 * rtol,
                "{name}, rodas: {what} error {err:.2e} > 30 rtol"
            );
        }
    }
}

/// DOP853 on the hydraulic scenes at tight tolerances: its steps end where the tool turns
/// (the orifice's `sd |sd|` is kinked there: `cushion_ode::kinks`), so it rejects at most one
/// attempt for every five steps it accepts (measured 0.15-0.2; 0.32-0.39 when it ran over the
/// kinks), and its four values lie within 30 rtol of the reference (measured: within 6.8
/// rtol, the robot impulse at 1e-9 on dt70).
#[test]
fn dop853_steps_on_the_orifice_kinks_and_converges() {
    for name in ["paper-hydraulic-dt70", "paper-hydraulic-dt10"] {
        let scene = paper(name);
        let reference = at(&scene, 1e-12);
        let mut dop853 = scene.clone();
        dop853.set_from_str("solver.method", "dop853").unwrap();
        for rtol in [1e-8, 1e-9, 1e-10] {
            let s = at(&dop853, rtol);
            let (steps, rejected) = (s.stats.steps, s.stats.rejected);
            assert!(
                5 * rejected <= steps,
                "{name}, rtol {rtol}: {rejected} of {steps} steps rejected"
            );
            for (err, what) in errors(&scene, &s, &reference).iter().zip(NAMES) {
                assert!(
                    *err <= 30.0 * rtol,
                    "{name}, dop853 at rtol {rtol}: {what} error {err:.2e} > 30 rtol"
                );
            }
        }
    }
}
