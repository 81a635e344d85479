//! Random scenes far outside the paper's: every key of docs/scene-keys.md drawn over a wide range
//! (masses 5 g-1 kg, approach speed 0.05-3 m/s, stiffnesses 1e4-1e8, rtol 1e-9-1e-3, ...),
//! each run twice: as given, and to `t_end` (early end and ringing tail off). Prints how the
//! runs ended and the worst differences between the two runs of each scene, relative to the
//! scene's own scales (speeds to `v_max`, the impulse to `(m_t + m_p) v_max`, forces to their
//! peak or 1 mN, strokes to the stroke; over the scenes that detect the impact), and lists
//! every run that did not end `ok` (a panic would end `invalid`, "internal error"), whose
//! ledger residual exceeds `1000 rtol`, or that detects the impact and differs by more than
//! `1000 rtol`: `wide_scenes [N] [SEED] [K] [--corners] [--method M]` (with K: print scene K as
//! TOML instead; `--corners`: 6 % of the scenes in the rarer corners of
//! `cushion_studies::wide`; `--method`: every adaptive scene under `dop853`, `rodas` or `auto`
//! instead of `dp5`).
use cushion_model::{simulate, RunOptions, RunStatus, Summary};

use cushion_studies::wide::{
    count_and_seed, draw, impact_counts, method_flag, with_method, Corners,
};
use cushion_studies::Uniform;

/// The summary fields compared between the two runs of a scene.
const NAMES: [&str; 6] = [
    "object_final_velocity",
    "robot_impulse",
    "peak_robot_force",
    "peak_contact_force",
    "max_stroke",
    "t_detect",
];

/// The two runs' differences in [`NAMES`]' order, each relative to the scene's own scale.
fn differences(s: &cushion_model::Scene, a: &Summary, b: &Summary) -> [f64; 6] {
    let v = s.robot.approach_speed;
    let m = s.tool.mass + if s.object.enabled { s.object.mass } else { 0.0 };
    [
        off(a.object_final_velocity, b.object_final_velocity, v),
        off(Some(a.robot_impulse), Some(b.robot_impulse), m * v),
        off(
            Some(a.peak_robot_force),
            Some(b.peak_robot_force),
            b.peak_robot_force.abs().max(1e-3),
        ),
        off(
            Some(a.peak_contact_force),
            Some(b.peak_contact_force),
            b.peak_contact_force.abs().max(1e-3),
        ),
        off(Some(a.max_stroke), Some(b.max_stroke), s.stops.stroke),
        off(a.t_detect, b.t_detect, s.t_end),
    ]
}

/// The closing report: how the runs ended, the worst differences, every flagged run.
fn print_tally(
    n: usize,
    refused: usize,
    statuses: &std::collections::BTreeMap<String, usize>,
    (detected, touched, fixed, idle_differ): (usize, usize, usize, usize),
    worst: &[(f64, usize)],
    worst_residual: (f64, usize),
    flagged: &[String],
) {
    println!("{n} scenes, {refused} refused by validate; statuses {statuses:?}; {detected} detect the impact, {touched} touch the object");
    for (k, name) in NAMES.iter().enumerate() {
        println!(
            "worst {name:<22} {:.2e} rtol (scene {})",
            worst[k].0, worst[k].1
        );
    }
    println!(
        "worst energy_residual      {:.2e} rtol (scene {})",
        worst_residual.0, worst_residual.1
    );
    println!("{fixed} scenes with a fixed-step method (ended ok, not compared)");
    println!(
        "{idle_differ} scenes that never detect the impact differ by more than 1000 rtol (noise-size forces)"
    );
    println!("{} flagged:", flagged.len());
    for f in flagged {
        println!("  {f}");
    }
}

/// `|a - b| / scale`, 0 when both are the same (also both NaN or both None).
fn off(a: Option<f64>, b: Option<f64>, scale: f64) -> f64 {
    match (a, b) {
        (Some(a), Some(b)) if a == b || (a.is_nan() && b.is_nan()) => 0.0,
        (Some(a), Some(b)) => (a - b).abs() / scale,
        (None, None) => 0.0,
        _ => f64::INFINITY,
    }
}

fn main() {
    // `--corners`: 6 % of the scenes in the rarer corners (the compressible liquid, fixed-step
    // methods, a low step limit, the stiffness test stopping the run)
    let mut all: Vec<String> = std::env::args().skip(1).collect();
    let method = method_flag(&mut all);
    let corners = if all.iter().any(|a| a == "--corners") {
        Corners::SOME
    } else {
        Corners::NONE
    };
    let mut args = all.into_iter().filter(|a| a != "--corners");
    let (n, seed) = count_and_seed(&mut args);
    // `wide_scenes N SEED K`: write scene K as TOML to standard output instead
    let show: Option<usize> = args.next().and_then(|a| a.parse().ok());
    let mut u = Uniform::new(seed);
    let mut worst = vec![(0.0f64, 0usize); NAMES.len()];
    let (mut refused, mut statuses) = (0, std::collections::BTreeMap::<String, usize>::new());
    let mut flagged = Vec::new();
    let (mut detected, mut touched, mut idle_differ, mut fixed) = (0, 0, 0, 0);
    let mut worst_residual = (0.0f64, 0usize);
    for i in 0..n {
        let s = with_method(draw(&mut u, corners), method.as_deref());
        if show == Some(i) {
            print!("{}", toml::to_string(&s.to_toml()).expect("a table"));
            return;
        }
        if let Err(e) = s.validate() {
            refused += 1;
            if refused <= 3 {
                println!("refused {i}: {e}");
            }
            continue;
        }
        let a = simulate(&s, &RunOptions::default()).summary;
        detected += usize::from(a.t_detect.is_some());
        touched += usize::from(a.object_impacts > 0);
        *statuses.entry(format!("{:?}", a.status)).or_default() += 1;
        if a.status != RunStatus::Ok {
            flagged.push(format!("{i}: {:?} {}", a.status, a.message));
            continue;
        }
        // the fixed-step methods keep no tolerance: their runs are not compared with it
        if !s.solver.method.is_adaptive() {
            fixed += 1;
            continue;
        }
        // flagged beyond 1000 rtol (NaN too)
        let limit = 1e3 * s.solver.rtol;
        let beyond = |d: f64| d > limit || d.is_nan();
        if let Some(r) = a.energy_residual {
            if r / s.solver.rtol > worst_residual.0 {
                worst_residual = (r / s.solver.rtol, i);
            }
            if beyond(r) {
                flagged.push(format!(
                    "{i}: energy_residual {r:.2e} at rtol {:.0e} ({}, detected {}, object touched {})",
                    s.solver.rtol,
                    s.module.name(),
                    a.t_detect.is_some(),
                    a.object_impacts > 0
                ));
            }
        }
        let mut full = s.clone();
        full.solver.early_end = false;
        full.solver.ringing_tail = false;
        let b = simulate(&full, &RunOptions::default()).summary;
        if b.status != RunStatus::Ok {
            flagged.push(format!("{i} (to t_end): {:?} {}", b.status, b.message));
            continue;
        }
        let diffs = differences(&s, &a, &b);
        let counts_differ = impact_counts(&a) != impact_counts(&b);
        // Against the tolerance, over the scenes that detect the impact: in the others the
        // forces are often of the size of the integration error itself (the tool riding along
        // at rest, F_r = 0 up to it), and at loose tolerances a full run's noise may even open
        // a stiff stop; those are counted apart.
        if a.t_detect.is_none() {
            idle_differ += usize::from(counts_differ || diffs.iter().any(|d| beyond(*d)));
            continue;
        }
        for (k, d) in diffs.iter().enumerate() {
            if *d / s.solver.rtol > worst[k].0 {
                worst[k] = (*d / s.solver.rtol, i);
            }
        }
        if counts_differ || diffs.iter().any(|d| beyond(*d)) {
            let what: Vec<String> = diffs
                .iter()
                .zip(NAMES)
                .filter(|(d, _)| beyond(**d))
                .map(|(d, n)| format!("{n} {d:.1e}"))
                .collect();
            flagged.push(format!(
                "{i}: early end vs t_end (rtol {:.0e}, {}): {}{}",
                s.solver.rtol,
                s.module.name(),
                what.join(", "),
                if counts_differ {
                    " impact counts differ"
                } else {
                    ""
                }
            ));
        }
    }
    print_tally(
        n,
        refused,
        &statuses,
        (detected, touched, fixed, idle_differ),
        &worst,
        worst_residual,
        &flagged,
    );
}
