//! Where a run spends its steps: `steps SCENE.toml [EDGE_MS]...` counts the accepted steps
//! that end in each interval between the given times (ms), up to the early end; without
//! edges, per 10 ms. Arguments with `=` set a scene key: `steps SCENE.toml module=bistable 5 80`.
//! (A ringing tail that ends at the robot's stop, where the run is integrated again, leaves
//! its trajectory points, 16 a period, among the steps it counts; the total is the solver's.)
use cushion_model::{simulate, RunOptions};
use cushion_studies::{scene_from, set_key};

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("steps SCENE.toml [KEY=VALUE]... [EDGE_MS]...");
    let mut scene = scene_from(Some(&path));
    let mut edges: Vec<f64> = Vec::new();
    for arg in args {
        if !set_key(&mut scene, &arg) {
            edges.push(arg.parse::<f64>().expect("a time in ms") * 1e-3);
        }
    }
    // steps and events only: every step end, plus a point per logged event
    let r = simulate(
        &scene,
        &RunOptions {
            trajectory: true,
            sample_interval: Some(0.0),
        },
    );
    let end = r
        .events
        .iter()
        .find(|e| e.name == "early_end")
        .map_or(scene.t_end, |e| e.t);
    if edges.is_empty() {
        edges = (1..)
            .map(|k| k as f64 * 0.01)
            .take_while(|&t| t < end)
            .collect();
    }
    let mut ends: Vec<f64> = r
        .trajectory
        .expect("recorded")
        .points
        .iter()
        .map(|p| p.t)
        .collect();
    ends.retain(|&t| t > 0.0 && t <= end);
    ends.dedup(); // an event's point shares the time of the step it cut
    let mut lo = 0.0;
    for &hi in edges.iter().chain(std::iter::once(&end)) {
        let n = ends.iter().filter(|&&t| t > lo && t <= hi).count();
        println!("{:>9.3} - {:>9.3} ms {:>5}", lo * 1e3, hi * 1e3, n);
        lo = hi;
    }
    println!("{:?}", r.summary.stats);
}
