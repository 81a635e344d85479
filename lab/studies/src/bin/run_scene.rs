//! Run one scene and print its summary and event log: `cargo run -p cushion-studies --bin
//! run_scene -- [SCENE.toml] [KEY=VALUE]...`.
use cushion_model::{simulate, RunOptions, Scene};
use cushion_studies::{scene_from, set_key};

fn main() {
    let mut scene = Scene::default();
    for arg in std::env::args().skip(1) {
        if !set_key(&mut scene, &arg) {
            scene = scene_from(Some(&arg));
        }
    }
    let r = simulate(&scene, &RunOptions::default());
    for e in &r.events {
        println!(
            "{:>10.6} {:<22} s={:.6} v_t={:.4} v_p={:.4} F_r={:.3}",
            e.t, e.name, e.point.s, e.point.v_t, e.point.v_p, e.point.f_r
        );
    }
    println!("{}", serde_json::to_string_pretty(&r.summary).unwrap());
}
