//! The recorded trajectories of the wide random scenes (`cushion_studies::wide`) against their
//! own summaries: `wide_trajectories [N] [SEED] [--corners] [--rtol R]` (`--rtol`: every scene
//! at that tolerance, atol 1e-3 of it, instead of its own). For each run that ends `ok` with an
//! adaptive method, the trajectory (every step, every event, samples every `t_end / 2000`) must
//! end at `t_end`, run forward in time, carry the summary's final object speed at its last
//! point, and stay within the summary's peaks: no sample of `|F_r|`, `F_c`, the stroke or the
//! gas pressure above the refined peak by more than rtol of its scale
//! (`cushion_studies::wide::peaks_and_samples`). Prints the runs that fail and the largest
//! excess of each kind, in rtol.
use cushion_model::RunStatus;

use cushion_studies::wide::{
    count_and_seed, draw, peaks_and_samples, run_recorded, trajectory_mismatches, Corners,
};
use cushion_studies::Uniform;

fn main() {
    let mut all: Vec<String> = std::env::args().skip(1).collect();
    let corners = if all.iter().any(|a| a == "--corners") {
        Corners::SOME
    } else {
        Corners::NONE
    };
    let rtol: Option<f64> = all.iter().position(|a| a == "--rtol").map(|i| {
        let r = all
            .get(i + 1)
            .and_then(|v| v.parse().ok())
            .expect("--rtol R");
        all.drain(i..i + 2);
        r
    });
    let mut args = all.into_iter().filter(|a| a != "--corners");
    let (n, seed) = count_and_seed(&mut args);
    let mut u = Uniform::new(seed);
    let mut worst = [(0.0f64, 0usize); 4];
    let (mut checked, mut failed) = (0, Vec::new());
    for i in 0..n {
        let mut s = draw(&mut u, corners);
        if let Some(r) = rtol {
            s.solver.rtol = r;
            s.solver.atol = r * 1e-3;
        }
        if s.validate().is_err() || !s.solver.method.is_adaptive() {
            continue;
        }
        let r = run_recorded(&s);
        let m = &r.summary;
        if m.status != RunStatus::Ok {
            continue;
        }
        checked += 1;
        let mut problems = trajectory_mismatches(&s, &r);
        for (k, (name, peak, top, scale)) in peaks_and_samples(&s, &r).into_iter().enumerate() {
            // relative to the scale, in units of rtol
            let excess = (top - peak) / scale / s.solver.rtol;
            if excess > worst[k].0 {
                worst[k] = (excess, i);
            }
            if excess > 1.0 {
                problems.push(format!(
                    "{name} sample {top} above the peak {peak} ({excess:.1} rtol)"
                ));
            }
        }
        if !problems.is_empty() {
            failed.push(format!(
                "{i} ({}, rtol {:.0e}{}): {}",
                s.module.name(),
                s.solver.rtol,
                if m.stats.stiff { ", stiff" } else { "" },
                problems.join("; ")
            ));
        }
    }
    println!("{checked} runs checked, {} with problems", failed.len());
    let names = ["|F_r|", "F_c", "stroke", "gas pressure"];
    for (name, (excess, scene)) in names.iter().zip(worst) {
        println!("largest sample above the peak, {name:<13} {excess:.2e} rtol (scene {scene})");
    }
    for f in &failed {
        println!("  {f}");
    }
}
