//! Print peak robot force, peak contact force and max stroke of random design-space scenes
//! (for comparing sampling strategies): `peaks_dump [N]`.
#![allow(clippy::field_reassign_with_default)]

use cushion_model::{simulate, RunOptions, Scene};
use cushion_studies::{draw_module_axes, Uniform};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(500);
    let mut u = Uniform::new(0x9E3779B97F4A7C15u64);
    for i in 0..n {
        let mut s = Scene::default();
        s.module = [
            cushion_model::Module::Hydraulic,
            cushion_model::Module::Bistable,
            cushion_model::Module::Rigid,
        ][i % 3];
        s.robot.dead_time = u.span(0.0, 0.1);
        draw_module_axes(&mut s, &mut u);
        let sm = simulate(&s, &RunOptions::default()).summary;
        println!(
            "{} {:.12e} {:.12e} {:.12e}",
            i, sm.peak_robot_force, sm.peak_contact_force, sm.max_stroke
        );
    }
}
