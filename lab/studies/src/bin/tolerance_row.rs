//! One row of the cost-against-accuracy study of a scene (`python -m lab.scene_tolerances`):
//! `tolerance_row SCENE.toml RTOL` runs the scene at `solver.rtol = RTOL`,
//! `solver.atol = RTOL / 1000` (the paper scenes' ratio) and at rtol 1e-12 as the reference, and
//! prints the steps, right-hand-side evaluations, the best wall time per run, and the errors of
//! the summary values a designer reads, as one JSON object (absent values are null).
use cushion_model::{simulate, RunOptions, Scene, Summary};

fn at_rtol(scene: &Scene, rtol: f64) -> Scene {
    let mut s = scene.clone();
    s.set_from_str("solver.rtol", &rtol.to_string())
        .expect("a valid rtol");
    s.set_from_str("solver.atol", &(rtol * 1e-3).to_string())
        .expect("a valid atol");
    s
}

fn run(scene: &Scene) -> Summary {
    simulate(scene, &RunOptions::default()).summary
}

/// Best time per run (µs) over 5 batches of about 50 ms each.
fn best_micros(scene: &Scene) -> f64 {
    let t = std::time::Instant::now();
    run(scene);
    let once = t.elapsed().as_secs_f64();
    let n = ((0.05 / once) as usize).clamp(1, 5000);
    (0..5)
        .map(|_| {
            let t = std::time::Instant::now();
            for _ in 0..n {
                std::hint::black_box(run(std::hint::black_box(scene)));
            }
            t.elapsed().as_secs_f64() / n as f64 * 1e6
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let usage = "tolerance_row SCENE.toml RTOL";
    let path = args.next().expect(usage);
    let rtol: f64 = args.next().expect(usage).parse().expect("RTOL: a number");
    let scene = Scene::from_file(std::path::Path::new(&path)).expect("readable scene");
    let (this, reference) = (at_rtol(&scene, rtol), at_rtol(&scene, 1e-12));
    let (s, r) = (run(&this), run(&reference));
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(f64::MIN_POSITIVE);
    // An optional value's error: null where neither run has it, "differs" where one has.
    let abs_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => serde_json::json!((a - b).abs()),
        (None, None) => serde_json::Value::Null,
        _ => serde_json::json!("differs"),
    };
    let counts = |x: &Summary| {
        [
            x.object_impacts,
            x.forward_stop_impacts,
            x.back_stop_impacts,
        ]
    };
    let row = serde_json::json!({
        "rtol": rtol,
        "steps": s.stats.steps,
        "rhs_evals": s.stats.rhs_evals,
        "us_per_run": best_micros(&this),
        "t_detect": abs_opt(s.t_detect, r.t_detect),
        "peak_robot_force_rel": rel(s.peak_robot_force, r.peak_robot_force),
        "robot_impulse": (s.robot_impulse - r.robot_impulse).abs(),
        "object_final_velocity": abs_opt(s.object_final_velocity, r.object_final_velocity),
        "max_stroke": (s.max_stroke - r.max_stroke).abs(),
        "energy_residual": s.energy_residual,
        "impacts": counts(&s),
        "reference_impacts": counts(&r),
    });
    println!("{row}");
}
