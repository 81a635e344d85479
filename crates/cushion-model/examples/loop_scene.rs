//! Run one scene many times (for profilers and instruction counts):
//! `loop_scene N [SCENE.toml] [KEY=VALUE]...` (without a file: the defaults).
use cushion_model::{simulate, RunOptions, Scene};
fn main() {
    let mut args = std::env::args().skip(1).peekable();
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let mut scene = match args.peek() {
        Some(a) if a.ends_with(".toml") => {
            Scene::from_file(std::path::Path::new(&args.next().unwrap())).expect("readable scene")
        }
        _ => Scene::default(),
    };
    for arg in args {
        let (k, v) = arg.split_once('=').expect("KEY=VALUE");
        scene.set_from_str(k, v).expect("valid");
    }
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for _ in 0..n {
        acc += simulate(&scene, &RunOptions::default())
            .summary
            .robot_impulse;
    }
    let dt = t.elapsed().as_secs_f64() / n.max(1) as f64;
    println!("{:.1} us/run ({acc})", dt * 1e6);
}
