//! Accuracy far from the paper's scenes: the wide random scenes of `cushion_studies::wide`, each
//! run at the default tolerance (rtol 1e-6, atol 1e-9) and at rtol 1e-11 (atol 1e-14) as the
//! reference. Prints, over the scenes that detect an impact, the median, 99th percentile and
//! largest error of each summary value relative to its scale (speeds to `v_max`, the impulse to
//! the larger of itself and `(m_t + m_p) v_max`, the peak force to itself, the stroke to the stroke length, the
//! detection time to `t_end`), how many runs' impact counts differ, and the worst scenes:
//! `wide_accuracy [N] [SEED] [--method M]` (print a scene with `wide_scenes N SEED K`: the same
//! draw; `--method`: the runs at rtol 1e-6 under `dop853`, `rodas` or `auto`, the reference
//! still `dp5`).
use cushion_model::{simulate, RunOptions, RunStatus, Scene, Summary};

use cushion_studies::wide::{
    count_and_seed, draw, impact_counts, method_flag, with_method, Corners,
};
use cushion_studies::Uniform;

fn run(s: &Scene, rtol: f64, atol: f64) -> Summary {
    let mut s = s.clone();
    s.solver.rtol = rtol;
    s.solver.atol = atol;
    simulate(&s, &RunOptions::default()).summary
}

fn main() {
    let mut all: Vec<String> = std::env::args().skip(1).collect();
    let method = method_flag(&mut all);
    let mut args = all.into_iter();
    let (n, seed) = count_and_seed(&mut args);
    let mut u = Uniform::new(seed);
    let names = [
        "object_final_velocity",
        "robot_impulse",
        "peak_robot_force",
        "peak_contact_force",
        "max_gas_pressure",
        "max_stroke",
        "t_detect",
    ];
    let mut errors: Vec<Vec<(f64, usize)>> = vec![Vec::new(); names.len()];
    let (mut compared, mut counts_differ, mut not_ok) = (0, Vec::new(), Vec::new());
    for i in 0..n {
        let s = draw(&mut u, Corners::NONE);
        let a = run(&with_method(s.clone(), method.as_deref()), 1e-6, 1e-9);
        let b = run(&s, 1e-11, 1e-14);
        if a.status != RunStatus::Ok || b.status != RunStatus::Ok {
            not_ok.push(format!(
                "{i}: {:?} / {:?} {}{}",
                a.status, b.status, a.message, b.message
            ));
            continue;
        }
        if b.t_detect.is_none() {
            continue;
        }
        compared += 1;
        let v = s.robot.approach_speed;
        let m = s.tool.mass + if s.object.enabled { s.object.mass } else { 0.0 };
        let speed = |x: &Summary| x.object_final_velocity.unwrap_or(0.0);
        let detect = |x: &Summary| x.t_detect.unwrap_or(f64::INFINITY);
        let e = [
            (speed(&a) - speed(&b)).abs() / v,
            (a.robot_impulse - b.robot_impulse).abs() / (m * v).max(b.robot_impulse.abs()),
            (a.peak_robot_force - b.peak_robot_force).abs() / b.peak_robot_force.abs(),
            (a.peak_contact_force - b.peak_contact_force).abs()
                / b.peak_contact_force.abs().max(1e-3),
            match (a.max_gas_pressure, b.max_gas_pressure) {
                (Some(x), Some(y)) => (x - y).abs() / y.abs(),
                _ => 0.0,
            },
            (a.max_stroke - b.max_stroke).abs() / s.stops.stroke,
            (detect(&a) - detect(&b)).abs() / s.t_end,
        ];
        for (k, x) in e.iter().enumerate() {
            errors[k].push((if x.is_nan() { f64::INFINITY } else { *x }, i));
        }
        if impact_counts(&a) != impact_counts(&b) {
            counts_differ.push(i);
        }
    }
    println!(
        "{n} scenes, {compared} detect an impact (compared at rtol 1e-6 against 1e-11), {} not ok",
        not_ok.len()
    );
    println!(
        "{:<22} {:>9} {:>9} {:>9}  worst scenes",
        "", "median", "p99", "largest"
    );
    for (k, name) in names.iter().enumerate() {
        let v = &mut errors[k];
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        if v.is_empty() {
            continue;
        }
        let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize].0;
        let worst: Vec<String> = v
            .iter()
            .rev()
            .take(4)
            .map(|(x, i)| format!("{i} ({x:.1e})"))
            .collect();
        println!(
            "{name:<22} {:>9.1e} {:>9.1e} {:>9.1e}  {}",
            q(0.5),
            q(0.99),
            q(1.0),
            worst.join(", ")
        );
    }
    println!(
        "impact counts differ in {} runs: {:?}",
        counts_differ.len(),
        counts_differ
    );
    for line in &not_ok {
        println!("  {line}");
    }
}
