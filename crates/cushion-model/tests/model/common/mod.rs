//! What several test files need: a paper scene or a kept scene with overrides, a run that must
//! end ok, and the reference run of a kept scene.
#![allow(dead_code)]

pub mod whole_runs;

use cushion_model::{simulate, RunOptions, RunStatus, Scene, Summary};

/// `sweeps/scenes/NAME.toml` with `sets` applied (`KEY`, `VALUE` as typed after `--set`).
pub fn paper(name: &str, sets: &[(&str, &str)]) -> Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../sweeps/scenes")
        .join(format!("{name}.toml"));
    let mut s = Scene::from_file(&p).unwrap();
    for (k, v) in sets {
        s.set_from_str(k, v).unwrap();
    }
    s
}

/// The summary of a run that must end `ok`.
pub fn run_ok(s: &Scene) -> Summary {
    let r = simulate(s, &RunOptions::default()).summary;
    assert_eq!(r.status, RunStatus::Ok, "{}", r.message);
    r
}

/// `tests/scenes/NAME.toml` (scenes kept for a test, most drawn by the wide-scene study binaries
/// of `lab/studies`) with `sets` applied.
pub fn kept_scene(name: &str, sets: &[(&str, &str)]) -> Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/scenes")
        .join(format!("{name}.toml"));
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    for (k, v) in sets {
        s.set_from_str(k, v).unwrap();
    }
    s
}

/// The summary of `s` at rtol 1e-11 (atol 1e-14), which must end `ok`: the reference a kept
/// scene's run is checked against.
pub fn reference(mut s: Scene) -> Summary {
    s.solver.rtol = 1e-11;
    s.solver.atol = 1e-14;
    run_ok(&s)
}
