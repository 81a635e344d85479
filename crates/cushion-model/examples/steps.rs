//! Where a run spends its steps: step ends per 10 ms bin.
use cushion_model::{simulate, RunOptions, Scene};
fn main() {
    let mut scene = Scene::default();
    for arg in std::env::args().skip(1) {
        let (k, v) = arg.split_once('=').expect("KEY=VALUE");
        scene.set_from_str(k, v).expect("valid");
    }
    let r = simulate(
        &scene,
        &RunOptions {
            trajectory: true,
            sample_interval: None,
        },
    );
    let pts = r.trajectory.unwrap().points;
    let mut bins = vec![0; (scene.t_end / 0.01).ceil() as usize + 1];
    for p in &pts {
        bins[(p.t / 0.01) as usize] += 1;
    }
    for (i, b) in bins.iter().enumerate() {
        println!("{:>5.2} {:>4} {}", i as f64 * 0.01, b, "#".repeat(*b / 2));
    }
    println!("{:?}", r.summary.stats);
}
