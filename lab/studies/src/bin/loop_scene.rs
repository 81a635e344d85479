//! Run one scene many times (for profilers and instruction counts):
//! `loop_scene N [SCENE.toml] [KEY=VALUE]...` (without a file: the defaults).
use cushion_model::{simulate, RunOptions};
use cushion_studies::{scene_from, set_key};

fn main() {
    let mut args = std::env::args().skip(1).peekable();
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let path = args.next_if(|a| a.ends_with(".toml"));
    let mut scene = scene_from(path.as_deref());
    for arg in args {
        assert!(set_key(&mut scene, &arg), "{arg}: not KEY=VALUE");
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
