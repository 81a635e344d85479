//! The recorded trajectories of the wide random scenes (`support/wide.rs`) against their own
//! summaries: `wide_trajectories [N] [SEED] [--corners] [--rtol R]` (`--rtol`: every scene at
//! that tolerance, atol 1e-3 of it, instead of its own). For each run that ends `ok` with an
//! adaptive method, the trajectory (every step, every event, samples every `t_end / 2000`) must
//! end at `t_end`, run forward in time, carry the summary's final object speed at its last
//! point, and stay within the summary's peaks: no sample of `|F_r|`, `F_c`, the stroke or the
//! gas pressure above the refined peak by more than rtol of its scale (forces: the peak or
//! 1 mN; the stroke: the stroke length; the gas pressure: its peak). The peaks are searched on
//! the same dense output, so a sample above one is a peak the search missed. Prints the runs
//! that fail and the largest excess of each kind, in rtol.
use cushion_model::{RunStatus, TrajectoryPoint};

mod support;
use support::wide::{count_and_seed, draw, run_recorded, Corners};

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
    let mut u = support::Uniform::new(seed);
    let names = ["|F_r|", "F_c", "stroke", "gas pressure"];
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
        let pts = &r.trajectory.as_ref().expect("recorded").points;
        let last = pts.last().expect("a point");
        let mut problems = Vec::new();
        if last.t != s.t_end {
            problems.push(format!("ends at {} not t_end {}", last.t, s.t_end));
        }
        if pts.windows(2).any(|w| w[1].t < w[0].t) {
            problems.push("time runs backwards".to_string());
        }
        if let Some(v) = m.object_final_velocity {
            if last.v_p != v {
                problems.push(format!("last v_p {} vs summary {v}", last.v_p));
            }
        }
        // (value at the peak, the sampled quantity, its scale: forces to their peak or 1 mN,
        // the stroke to the stroke length, the gas pressure to its peak)
        type Of = fn(&TrajectoryPoint) -> f64;
        let peaks: [(f64, Of, f64); 4] = [
            (
                m.peak_robot_force.abs(),
                |p| p.f_r.abs(),
                m.peak_robot_force.abs().max(1e-3),
            ),
            (
                m.peak_contact_force,
                |p| p.f_c,
                m.peak_contact_force.max(1e-3),
            ),
            (m.max_stroke, |p| p.s, s.stops.stroke),
            (
                m.max_gas_pressure.unwrap_or(f64::INFINITY),
                |p| p.p1,
                m.max_gas_pressure.unwrap_or(1.0),
            ),
        ];
        for (k, (peak, f, scale)) in peaks.iter().enumerate() {
            let top = pts
                .iter()
                .map(f)
                .filter(|v| v.is_finite())
                .fold(f64::NEG_INFINITY, f64::max);
            // relative to the scale, in units of rtol
            let excess = (top - peak) / scale / s.solver.rtol;
            if excess > worst[k].0 {
                worst[k] = (excess, i);
            }
            if excess > 1.0 {
                problems.push(format!(
                    "{} sample {top} above the peak {peak} ({excess:.1} rtol)",
                    names[k]
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
    for (k, name) in names.iter().enumerate() {
        println!(
            "largest sample above the peak, {name:<13} {:.2e} rtol (scene {})",
            worst[k].0, worst[k].1
        );
    }
    for f in &failed {
        println!("  {f}");
    }
}
