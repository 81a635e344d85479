//! Helpers of the whole-run tests (`runs.rs`, `early_end.rs`, `friction_and_contacts.rs`,
//! `statuses.rs`): a paper scene, overrides, runs that must end ok, and summary comparisons.
#![allow(dead_code)]

use cushion_model::{simulate, RunOptions, RunResult, RunStatus, Scene, Summary};

pub fn paper(name: &str) -> Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../sweeps/scenes/{name}.toml"));
    Scene::from_file(&p).unwrap()
}

pub fn with(mut s: Scene, sets: &[(&str, &str)]) -> Scene {
    for (k, v) in sets {
        s.set_from_str(k, v).unwrap();
    }
    s
}

pub fn tight(s: Scene) -> Scene {
    with(s, &[("solver.rtol", "1e-10"), ("solver.atol", "1e-13")])
}

pub fn run(s: &Scene) -> RunResult {
    let r = simulate(s, &RunOptions::default());
    assert_eq!(r.summary.status, RunStatus::Ok, "{}", r.summary.message);
    r
}

pub fn run_traj(s: &Scene, dt: f64) -> RunResult {
    let r = simulate(
        s,
        &RunOptions {
            trajectory: true,
            sample_interval: Some(dt),
        },
    );
    assert_eq!(r.summary.status, RunStatus::Ok, "{}", r.summary.message);
    r
}

/// When the run's first event named `name` happened (s), if it did.
pub fn event_time(r: &RunResult, name: &str) -> Option<f64> {
    r.events.iter().find(|e| e.name == name).map(|e| e.t)
}

pub fn close(a: f64, b: f64, rel: f64, abs: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + abs
}

pub fn assert_same(a: &Summary, b: &Summary, rel: f64, what: &str) {
    let pairs = [
        ("peak_robot_force", a.peak_robot_force, b.peak_robot_force),
        ("robot_impulse", a.robot_impulse, b.robot_impulse),
        (
            "peak_contact_force",
            a.peak_contact_force,
            b.peak_contact_force,
        ),
        ("max_stroke", a.max_stroke, b.max_stroke),
        (
            "object_final_velocity",
            a.object_final_velocity.unwrap_or(0.0),
            b.object_final_velocity.unwrap_or(0.0),
        ),
        (
            "object_travel",
            a.object_travel.unwrap_or(0.0),
            b.object_travel.unwrap_or(0.0),
        ),
        (
            "t_detect",
            a.t_detect.unwrap_or(0.0),
            b.t_detect.unwrap_or(0.0),
        ),
    ];
    for (name, x, y) in pairs {
        let abs = if name.contains("force") || name.contains("impulse") {
            1e-6
        } else {
            1e-9
        };
        assert!(close(x, y, rel, abs), "{what}: {name} {x} vs {y}");
    }
    assert_eq!(a.object_impacts, b.object_impacts, "{what}");
    assert_eq!(a.back_stop_hit, b.back_stop_hit, "{what}");
}
