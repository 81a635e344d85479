//! Print peak robot force, peak contact force and max stroke of random design-space scenes
//! (for comparing sampling strategies): `peaks_dump [N]`.
#![allow(clippy::field_reassign_with_default)]

use cushion_model::{simulate, RunOptions, Scene};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(500);
    let mut state = 0x9E3779B97F4A7C15u64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..n {
        let mut s = Scene::default();
        s.module = [
            cushion_model::Module::Hydraulic,
            cushion_model::Module::Bistable,
            cushion_model::Module::Rigid,
        ][i % 3];
        s.robot.dead_time = 0.1 * rnd();
        s.hydraulic.gas_pressure = (300f64.ln() + (1e5f64.ln() - 300f64.ln()) * rnd()).exp();
        s.hydraulic.orifice_radius = 0.002 + 0.010 * rnd();
        s.object.mass = 0.05 + 0.95 * rnd();
        let sm = simulate(&s, &RunOptions::default()).summary;
        println!(
            "{} {:.12e} {:.12e} {:.12e}",
            i, sm.peak_robot_force, sm.peak_contact_force, sm.max_stroke
        );
    }
}
