//! The ringing tail against running to `t_end`: random scenes of the design space (module,
//! dead time, gas pressure, orifice, object mass, brake deceleration), each run with
//! `solver.ringing_tail` on and off; prints the steps saved and the worst difference of each
//! summary value (robot impulse relative to the momentum scale `(m_t + m_p) v_max`, energy
//! residual absolute, the others relative): `ringing_tail_check [N] [KEY=VALUE]...`.
use cushion_model::{simulate, Module, RunOptions, Scene};
use cushion_studies::{draw_module_axes, set_key, Uniform};

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(200);
    let sets: Vec<String> = args.collect();
    let mut u = Uniform::new(0x9E3779B97F4A7C15u64);
    let names = [
        "robot_impulse",
        "object_final_velocity",
        "peak_robot_force",
        "max_stroke",
        "energy_residual",
    ];
    let mut worst: Vec<(f64, String)> = vec![(0.0, String::new()); 5];
    let (mut steps_on, mut steps_off, mut tails, mut differ_counts) = (0u64, 0u64, 0, 0);
    for i in 0..n {
        let mut s = Scene {
            module: if i % 2 == 0 {
                Module::Hydraulic
            } else {
                Module::Bistable
            },
            ..Scene::default()
        };
        s.robot.dead_time = u.span(0.0, 0.1);
        s.robot.brake_deceleration = u.span(5.0, 25.0);
        draw_module_axes(&mut s, &mut u);
        for arg in &sets {
            assert!(set_key(&mut s, arg), "{arg}: not KEY=VALUE");
        }
        let desc = format!(
            "--set module={} --set robot.dead_time={} --set robot.brake_deceleration={} --set hydraulic.gas_pressure={} --set hydraulic.orifice_radius={} --set object.mass={}",
            if s.module == Module::Hydraulic { "hydraulic" } else { "bistable" }, s.robot.dead_time, s.robot.brake_deceleration, s.hydraulic.gas_pressure,
            s.hydraulic.orifice_radius, s.object.mass
        );
        let on = simulate(&s, &RunOptions::default());
        s.solver.ringing_tail = false;
        let off = simulate(&s, &RunOptions::default());
        if on.events.iter().any(|e| e.name == "early_end")
            && on.summary.stats.steps < off.summary.stats.steps
        {
            tails += 1;
        }
        steps_on += on.summary.stats.steps;
        steps_off += off.summary.stats.steps;
        let (a, b) = (&on.summary, &off.summary);
        if a.object_impacts != b.object_impacts
            || a.forward_stop_impacts != b.forward_stop_impacts
            || a.back_stop_impacts != b.back_stop_impacts
            || a.status != b.status
        {
            differ_counts += 1;
            println!("counts differ: {desc}");
        }
        let vals = |x: &cushion_model::Summary| {
            [
                x.robot_impulse,
                x.object_final_velocity.unwrap_or(0.0),
                x.peak_robot_force,
                x.max_stroke,
                x.energy_residual.unwrap_or(0.0),
            ]
        };
        let (va, vb) = (vals(a), vals(b));
        for k in 0..5 {
            // impulse: relative to the momentum scale (m_t + m_p) v_max, as the integrator's
            // tolerance sees it; the residual: absolute; the rest: relative
            let momentum = (s.tool.mass + s.object.mass) * s.robot.approach_speed;
            let d = match k {
                0 => (va[k] - vb[k]).abs() / momentum,
                4 => (va[k] - vb[k]).abs(),
                _ => (va[k] - vb[k]).abs() / vb[k].abs().max(1e-12),
            };
            if d > worst[k].0 {
                worst[k] = (d, desc.clone());
            }
        }
    }
    println!("{n} scenes, ringing tail taken in {tails}; steps {steps_off} -> {steps_on} ({:.2}x fewer); counts differ in {differ_counts}", steps_off as f64 / steps_on as f64);
    for k in 0..5 {
        println!("worst {:<22} {:.2e}  {}", names[k], worst[k].0, worst[k].1);
    }
}
