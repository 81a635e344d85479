//! What several test files need: a paper scene with overrides, and a run that must end ok.
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
