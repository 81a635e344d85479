//! Run random scenes of issue 4's design space (dead time 0-0.1 s, gas 300 Pa-100 kPa log,
//! orifice 2-12 mm, object mass 0.05-1 kg, hydraulic and bistable) and report statuses,
//! cost and the worst energy residual: `design_sample [N]`.
#![allow(clippy::field_reassign_with_default)]

use cushion_model::{simulate, RunOptions, RunStatus, Scene};
use cushion_studies::{draw_module_axes, Uniform};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let mut u = Uniform::new(0x2545F4914F6CDD1Du64);
    let mut counts = std::collections::BTreeMap::new();
    let mut worst: (f64, String) = (0.0, String::new());
    let mut max_rhs = (0u64, String::new());
    let mut rhs_total = 0u64;
    let t0 = std::time::Instant::now();
    for i in 0..n {
        let mut s = Scene::default();
        s.module = if i % 2 == 0 {
            cushion_model::Module::Hydraulic
        } else {
            cushion_model::Module::Bistable
        };
        s.robot.dead_time = u.span(0.0, 0.1);
        draw_module_axes(&mut s, &mut u);
        let r = simulate(&s, &RunOptions::default());
        let sm = r.summary;
        *counts.entry(sm.status.name()).or_insert(0) += 1;
        let desc = format!(
            "module={} robot.dead_time={} hydraulic.gas_pressure={} hydraulic.orifice_radius={} object.mass={}",
            s.module.name(),
            s.robot.dead_time,
            s.hydraulic.gas_pressure,
            s.hydraulic.orifice_radius,
            s.object.mass
        );
        if sm.status != RunStatus::Ok && counts[sm.status.name()] <= 3 {
            println!("{}: {} ({desc})", sm.status.name(), sm.message);
        }
        if let Some(e) = sm.energy_residual {
            if e > worst.0 {
                worst = (e, desc.clone());
            }
        }
        rhs_total += sm.stats.rhs_evals;
        if sm.stats.rhs_evals > max_rhs.0 {
            max_rhs = (sm.stats.rhs_evals, desc);
        }
    }
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "{n} runs, {:.1} us/run, {:.0} rhs/run on average",
        dt / n as f64 * 1e6,
        rhs_total as f64 / n as f64
    );
    println!("statuses: {counts:?}");
    println!("worst energy residual {:.2e} ({})", worst.0, worst.1);
    println!("most rhs evaluations {} ({})", max_rhs.0, max_rhs.1);
}
