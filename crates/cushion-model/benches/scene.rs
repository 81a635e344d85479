//! Cost of one run of each paper scene at rtol 1e-6 (in-process, release), and the cost of
//! optional parts absent vs present. Not a test: `cargo bench -p cushion-model --bench scene`.

use cushion_model::model::Layout;
use cushion_model::{simulate, RunOptions, Scene};
use std::hint::black_box;
use std::time::{Duration, Instant};

fn scene(name: &str) -> Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../sweeps/scenes/{name}.toml"));
    Scene::from_file(&p).expect("shipped scene")
}

fn with(mut s: Scene, sets: &[(&str, &str)]) -> Scene {
    for (k, v) in sets {
        s.set_from_str(k, v).expect("valid key");
    }
    s
}

/// Median of several batches, each running at least `budget / batches`.
fn time_per_run(s: &Scene, budget: Duration) -> f64 {
    let opts = RunOptions::default();
    // warm up
    for _ in 0..20 {
        black_box(simulate(black_box(s), &opts));
    }
    let batches = 7;
    let mut per = Vec::new();
    for _ in 0..batches {
        let start = Instant::now();
        let mut n = 0u32;
        while start.elapsed() < budget / batches {
            black_box(simulate(black_box(s), &opts));
            n += 1;
        }
        per.push(start.elapsed().as_secs_f64() / n as f64);
    }
    per.sort_by(|a, b| a.total_cmp(b));
    per[batches as usize / 2]
}

fn row(label: &str, s: &Scene) {
    let r = simulate(s, &RunOptions::default());
    let t = time_per_run(s, Duration::from_millis(700));
    let st = r.summary.stats;
    println!(
        "{:<44} {:>3} {:>9.1} {:>7} {:>6} {:>5} {:>8.1} {:>10.5}",
        label,
        Layout::of(s).n,
        t * 1e6,
        st.rhs_evals,
        st.steps,
        st.rejected,
        t * 1e9 / st.rhs_evals as f64,
        r.summary.object_final_velocity.unwrap_or(f64::NAN),
    );
}

fn main() {
    println!(
        "cushion-model: one run per scene, rtol 1e-6, atol 1e-9, in-process (median of 7 batches)"
    );
    println!(
        "{:<44} {:>3} {:>9} {:>7} {:>6} {:>5} {:>8} {:>10}",
        "scene", "N", "us/run", "rhs", "steps", "rej", "ns/rhs", "v_p(end)"
    );
    for name in [
        "paper-hydraulic-dt70",
        "paper-hydraulic-dt10",
        "paper-bistable-dt70",
        "paper-bistable-dt10",
        "paper-rigid",
    ] {
        row(name, &scene(name));
    }
    println!();
    println!("optional parts absent vs present (paper-hydraulic-dt70 unless named)");
    let h = scene("paper-hydraulic-dt70");
    row(
        "ledger off (tool + object: 4 states)",
        &with(h.clone(), &[("energy.ledger", "false")]),
    );
    row("ledger on (default: 6 states)", &h);
    row(
        "ledger on + idle plane friction (far object)",
        &with(
            h.clone(),
            &[("object.gap", "1.0"), ("object.plane_friction", "0.5")],
        ),
    );
    row(
        "far object, no plane friction",
        &with(h.clone(), &[("object.gap", "1.0")]),
    );
    row(
        "no object, ledger off (2 states)",
        &with(
            h.clone(),
            &[("object.enabled", "false"), ("energy.ledger", "false")],
        ),
    );
    row(
        "dry friction 2 N (stick-slip events)",
        &with(h.clone(), &[("tool.dry_friction", "2")]),
    );
    row(
        "plane friction 0.5 (stick phase)",
        &with(h.clone(), &[("object.plane_friction", "0.5")]),
    );
    row(
        "ringing tail off (integrated to t_end)",
        &with(h.clone(), &[("solver.ringing_tail", "false")]),
    );
    row(
        "bistable dt70, ringing tail off",
        &with(
            scene("paper-bistable-dt70"),
            &[("solver.ringing_tail", "false")],
        ),
    );
    row(
        "early end off, t_end 1.5 s",
        &with(
            h.clone(),
            &[("t_end", "1.5"), ("solver.early_end", "false")],
        ),
    );
    row(
        "early end on, t_end 1.5 s",
        &with(h.clone(), &[("t_end", "1.5")]),
    );
    let rg = scene("paper-rigid");
    row(
        "rigid, ledger off (2 states)",
        &with(rg.clone(), &[("energy.ledger", "false")]),
    );
    row(
        "rigid, early end off",
        &with(rg, &[("solver.early_end", "false")]),
    );
}
