//! Whole runs against physics: Newton's third law, preload equilibrium, energy ledger, the paper's
//! four results (`docs/model.md`) on the shipped paper scenes, idle and absent parts, the robot
//! impulse, the event log, the compressible liquid. Early ends, friction and contacts, and statuses
//! have their own files.

use cushion_model::model::Layout;
use cushion_model::physics::{bistable_force, gas_pressure, hunt_crossley, orifice_pressure_drop};
use cushion_model::{simulate, Module, RunOptions, RunStatus, Scene, TrajectoryPoint};

use crate::common::whole_runs::*;

/// The module force on the tool `G`, computed here from a trajectory point and the scene alone
/// (independent of the model's code paths); `F_r` must be `-G`.
fn module_force(s: &Scene, p: &TrajectoryPoint) -> f64 {
    let sd = p.v_r - p.v_t;
    let st = &s.stops;
    let f_fwd = hunt_crossley(st.stiffness, st.damping, -p.s, -sd);
    let f_back = hunt_crossley(st.stiffness, st.damping, p.s - st.stroke, sd);
    let b = s.tool.viscous_friction * sd;
    let module = match s.module {
        Module::Hydraulic => {
            let h = &s.hydraulic;
            let p1 = gas_pressure(
                h.gas_pressure,
                h.gas_volume,
                s.piston_area(),
                h.gas_exponent,
                p.s,
            );
            assert!((p1 - p.p1).abs() <= 1e-12 * p1, "p1 {} vs {}", p1, p.p1);
            let dp = orifice_pressure_drop(
                h.loss_coefficient,
                h.liquid_density,
                s.piston_area(),
                s.orifice_area(),
                sd,
            );
            (p1 + dp) * s.piston_area()
        }
        Module::Bistable => {
            let bi = &s.bistable;
            bistable_force(
                bi.spring_stiffness,
                bi.half_span,
                bi.apex_rise,
                p.s + bi.offset,
            )
        }
        Module::Rigid => unreachable!(),
    };
    module + b + f_back - f_fwd
}

fn contact_force(s: &Scene, p: &TrajectoryPoint) -> f64 {
    hunt_crossley(
        s.object.contact_stiffness,
        s.object.contact_damping,
        p.x_t - p.x_p,
        p.v_t - p.v_p,
    )
}

fn check_newton(s: &Scene) {
    let dt = 2e-5;
    let r = run_traj(s, dt);
    let pts = &r.trajectory.as_ref().unwrap().points;
    let peak = r.summary.peak_robot_force.abs();
    assert!(pts.len() > 1000);
    // 1. F_r = -G and F_c from the state, at every output point.
    for p in pts {
        let fc = contact_force(s, p);
        assert!(
            (fc - p.f_c).abs() <= 1e-9 * (1.0 + fc),
            "F_c at t = {}: {} vs {}",
            p.t,
            p.f_c,
            fc
        );
        if s.module != Module::Rigid {
            let g = module_force(s, p);
            assert!(
                (p.f_r + g).abs() <= 1e-9 * (1.0 + g.abs()),
                "F_r at t = {}: {} vs {}",
                p.t,
                p.f_r,
                -g
            );
        }
    }
    // 2. F_r = -(m_t a_t + F_c) with a_t from the motion itself (central differences of v_t on
    //    the uniform samples), away from events and kinks.
    let uniform: Vec<&TrajectoryPoint> = pts
        .iter()
        .filter(|p| ((p.t / dt).round() * dt - p.t).abs() < 1e-12 && p.t > 0.0)
        .collect();
    let ev: Vec<f64> = r.events.iter().map(|e| e.t).collect();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for w in uniform.windows(5) {
        let (a, b, c) = (w[0], w[2], w[4]);
        if (c.t - a.t - 4.0 * dt).abs() > 1e-9
            || ev
                .iter()
                .any(|&te| te >= a.t - 2.0 * dt && te <= c.t + 2.0 * dt)
        {
            continue;
        }
        // fourth-order central difference
        let a_t = (-w[4].v_t + 8.0 * w[3].v_t - 8.0 * w[1].v_t + w[0].v_t) / (12.0 * dt);
        let err = (b.f_r + s.tool.mass * a_t + b.f_c).abs();
        worst = worst.max(err);
        n += 1;
    }
    assert!(n > 1000, "{n}");
    assert!(
        worst <= 2e-4 * peak,
        "Newton's third law off by {worst} N (peak {peak} N)"
    );
}

#[test]
fn newton_third_law_hydraulic() {
    check_newton(&tight(paper("paper-hydraulic-dt70")));
}

#[test]
fn newton_third_law_bistable() {
    check_newton(&tight(paper("paper-bistable-dt10")));
}

#[test]
fn newton_third_law_rigid() {
    check_newton(&tight(paper("paper-rigid")));
}

#[test]
fn preload_equilibrium_holds_still() {
    for module in ["hydraulic", "bistable"] {
        // integrated to t_end (an early end would take over at once: nothing happens)
        let s = with(
            Scene::default(),
            &[
                ("module", module),
                ("object.enabled", "false"),
                ("solver.early_end", "false"),
            ],
        );
        let r = run_traj(&tight(s), 1e-3);
        let pts = &r.trajectory.unwrap().points;
        let s0 = pts[0].s;
        assert!(
            s0 < 0.0,
            "{module}: the preload presses the tool onto the forward stop"
        );
        for p in pts {
            // at rtol 1e-10, atol 1e-13: still to the solver's noise
            assert!(
                (p.s - s0).abs() < 1e-11,
                "{module}: s moved by {} at t = {}",
                p.s - s0,
                p.t
            );
            assert!(
                p.f_r.abs() < 1e-7,
                "{module}: F_r = {} at t = {}",
                p.f_r,
                p.t
            );
            assert!(
                (p.v_t - 1.0).abs() < 1e-9,
                "{module}: v_t - v_r = {} at t = {}",
                p.v_t - 1.0,
                p.t
            );
        }
        assert_eq!(r.summary.t_detect, None);
        assert!(r.events.is_empty(), "{:?}", r.events);
    }
}

#[test]
fn energy_ledger_closes_for_each_module() {
    let cases: Vec<(&str, Scene)> = vec![
        ("hydraulic dt70", paper("paper-hydraulic-dt70")),
        ("hydraulic dt10", paper("paper-hydraulic-dt10")),
        ("bistable dt70", paper("paper-bistable-dt70")),
        ("bistable dt10", paper("paper-bistable-dt10")),
        ("rigid", paper("paper-rigid")),
        (
            "hydraulic, dry + plane friction",
            with(
                paper("paper-hydraulic-dt70"),
                &[("tool.dry_friction", "2"), ("object.plane_friction", "0.5")],
            ),
        ),
        (
            "bistable, dry + plane friction",
            with(
                paper("paper-bistable-dt10"),
                &[("tool.dry_friction", "1"), ("object.plane_friction", "0.3")],
            ),
        ),
        (
            "rigid, plane friction, rest start",
            with(
                paper("paper-rigid"),
                &[("object.plane_friction", "0.4"), ("robot.start", "rest")],
            ),
        ),
        (
            "hydraulic, rest start",
            with(paper("paper-hydraulic-dt70"), &[("robot.start", "rest")]),
        ),
    ];
    for (name, s) in cases {
        let (r, ledger) = cushion_model::simulate_with_ledger(&tight(s), &RunOptions::default());
        assert_eq!(r.summary.status, RunStatus::Ok);
        let res = r.summary.energy_residual.unwrap();
        assert!(res < 1e-6, "{name}: residual {res}");
        // and to 1e-6 of the robot's work itself
        let l = ledger.unwrap();
        let mismatch = l.work - (l.kinetic + l.gas + l.elastic + l.dissipated);
        assert!(mismatch.abs() < 1e-6 * l.work.abs(), "{name}: {l:?}");
        assert!(l.dissipated > 0.0 && l.work.abs() > 1e-3, "{name}: {l:?}");
    }
    // and it is off (None) without the ledger
    let r = run(&with(Scene::default(), &[("energy.ledger", "false")]));
    assert_eq!(r.summary.energy_residual, None);
}

#[test]
fn the_ledger_residual_of_a_scene_where_nothing_happens_is_small() {
    // No object: the tool rides along at rest on its stop, the run ends after a step. The
    // work and every energy change are of rounding size (~1e-17 J); their mismatch over the
    // largest of them alone would be noise over noise (0.13 hydraulic, 0.27 bistable). Over the
    // largest term of `W + E(0) = E(t) + D`, which counts the tool's kinetic energy, it is
    // rounding again.
    for module in ["hydraulic", "bistable", "rigid"] {
        let s = with(
            Scene::default(),
            &[("module", module), ("object.enabled", "false")],
        );
        let (r, ledger) = cushion_model::simulate_with_ledger(&s, &RunOptions::default());
        assert_eq!(r.summary.status, RunStatus::Ok, "{module}");
        let l = ledger.unwrap();
        assert!(l.work.abs() < 1e-12, "{module}: {l:?}");
        assert!(l.residual < 1e-12, "{module}: {l:?}");
        assert_eq!(r.summary.energy_residual, Some(l.residual), "{module}");
    }
}

#[test]
fn claim_1_hydraulic_dt70_shape() {
    let s = paper("paper-hydraulic-dt70");
    let r = run_traj(&s, 1e-4);
    let pts = &r.trajectory.as_ref().unwrap().points;
    let sm = &r.summary;
    let t_brake = sm.t_brake.unwrap();
    let at = |t: f64| {
        pts.iter()
            .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
            .unwrap()
    };
    // at impact the tool slows down
    let begin = event_time(&r, "object_contact_begin").unwrap();
    assert!(at(begin + 3e-3).v_t < 0.7);
    // then tool and object move together (in contact, same speed) until after braking begins
    let end = event_time(&r, "object_contact_end").unwrap();
    assert!(end > t_brake);
    for t in [0.03, 0.05, t_brake - 1e-3] {
        let p = at(t);
        assert!(
            (p.v_t - p.v_p).abs() < 0.01 && p.f_c > 0.0,
            "t = {t}: {p:?}"
        );
    }
    // the gas pressure peaks when the robot starts braking and falls after it (gas expands while
    // the tool outruns the braking robot)
    let pmax = pts.iter().max_by(|a, b| a.p1.total_cmp(&b.p1)).unwrap();
    assert!(
        pmax.t > begin && pmax.t < t_brake,
        "p1 peaks at {}, brake at {t_brake}",
        pmax.t
    );
    assert!((pmax.p1 - sm.max_gas_pressure.unwrap()).abs() < 1e-3 * pmax.p1);
    // after braking begins the tool outruns the robot and the gas expands: p1 falls
    let after: Vec<_> = pts
        .iter()
        .filter(|p| p.t > t_brake && p.t < t_brake + 0.02)
        .collect();
    assert!(after.iter().all(|p| p.v_t > p.v_r));
    assert!(after.windows(2).all(|w| w[1].p1 <= w[0].p1));
    assert!(at(t_brake + 0.02).p1 < at(t_brake).p1 - 50.0);
    // two main peaks of opposite sign: the impact, and the tool returning onto the forward stop
    assert!(sm.peak_robot_force < 0.0 && sm.t_peak_robot_force < begin + 5e-3);
    let back_on_stop = event_time(&r, "forward_stop_begin").unwrap();
    let pos = pts
        .iter()
        .filter(|p| p.t > back_on_stop)
        .max_by(|a, b| a.f_r.total_cmp(&b.f_r))
        .unwrap();
    assert!(pos.f_r > 1.0, "second peak {} N at {}", pos.f_r, pos.t);
    // it is the largest force of its sign in the run
    let before = pts
        .iter()
        .filter(|p| p.t < back_on_stop)
        .map(|p| p.f_r)
        .fold(0.0, f64::max);
    assert!(
        before < pos.f_r,
        "positive force before the return: {before} N"
    );
}

#[test]
fn claim_2_hydraulic_peak_force_below_bistable() {
    for dt in ["dt70", "dt10"] {
        let h = run(&paper(&format!("paper-hydraulic-{dt}"))).summary;
        let b = run(&paper(&format!("paper-bistable-{dt}"))).summary;
        assert!(
            h.peak_robot_force.abs() < b.peak_robot_force.abs(),
            "{dt}: hydraulic {} N, bistable {} N",
            h.peak_robot_force,
            b.peak_robot_force
        );
    }
}

#[test]
fn claim_3_dt70_hydraulic_leaves_object_slower() {
    let h = run(&paper("paper-hydraulic-dt70")).summary;
    let b = run(&paper("paper-bistable-dt70")).summary;
    assert!(h.object_final_velocity.unwrap() < b.object_final_velocity.unwrap());
}

#[test]
fn claim_4_dt10_bistable_leaves_object_slower_and_peaks_at_back_stop() {
    let h = run(&paper("paper-hydraulic-dt10")).summary;
    let rb = run_traj(&paper("paper-bistable-dt10"), 1e-4);
    let b = &rb.summary;
    assert!(b.object_final_velocity.unwrap() < h.object_final_velocity.unwrap());
    // several tool-object impacts, later ones after the robot braked
    assert!(b.object_impacts >= 2);
    let t_brake = b.t_brake.unwrap();
    assert!(rb
        .events
        .iter()
        .filter(|e| e.name == "object_contact_begin")
        .any(|e| e.t > t_brake));
    // small first peak at impact, larger ones on the back stop
    let first_back = event_time(&rb, "back_stop_begin").unwrap();
    let pts = &rb.trajectory.as_ref().unwrap().points;
    let impact_peak = pts
        .iter()
        .filter(|p| p.t < first_back)
        .map(|p| p.f_r.abs())
        .fold(0.0, f64::max);
    assert!(b.back_stop_hit && b.back_stop_impacts >= 2);
    assert!(b.t_peak_robot_force > first_back);
    assert!(
        impact_peak < 0.5 * b.peak_robot_force.abs(),
        "impact {impact_peak} N, peak {} N",
        b.peak_robot_force
    );
}

#[test]
fn rigid_peak_force_exceeds_both_modules() {
    let rg = run(&paper("paper-rigid")).summary;
    for name in ["paper-hydraulic-dt70", "paper-bistable-dt70"] {
        let m = run(&paper(name)).summary;
        assert!(
            rg.peak_robot_force.abs() > m.peak_robot_force.abs(),
            "{name}"
        );
    }
    // rigid: detection at first contact
    let r = run(&paper("paper-rigid"));
    let first = event_time(&r, "object_contact_begin").unwrap();
    assert_eq!(r.summary.t_detect, Some(first));
    assert!((first - 1e-3).abs() < 1e-12);
}

#[test]
fn idle_parts_switched_on_do_not_change_results() {
    for name in ["paper-hydraulic-dt70", "paper-bistable-dt10", "paper-rigid"] {
        let base = with(
            paper(name),
            &[("solver.rtol", "1e-9"), ("solver.atol", "1e-12")],
        );
        let a = run(&base).summary;
        // the energy ledger only watches
        let b = run(&with(base.clone(), &[("energy.ledger", "false")])).summary;
        assert_same(&a, &b, 1e-5, &format!("{name}: ledger off"));
        // recording a trajectory only watches
        let c = run_traj(&base, 1e-4).summary;
        assert_eq!(a, c, "{name}: recording changed the summary");
        // plane friction on an object that is never touched, vs no friction and no object
        let far = with(base.clone(), &[("object.gap", "1.0")]);
        let d = run(&far).summary;
        let e = run(&with(far.clone(), &[("object.plane_friction", "0.5")])).summary;
        assert_same(&d, &e, 1e-5, &format!("{name}: idle plane friction"));
        let f = run(&with(far, &[("object.enabled", "false")])).summary;
        assert!(
            close(d.peak_robot_force, f.peak_robot_force, 1e-5, 1e-6)
                && close(d.max_stroke, f.max_stroke, 1e-5, 1e-12)
        );
        assert!(close(d.robot_impulse, f.robot_impulse, 1e-5, 1e-6));
    }
}

/// The ledger's quadratures add their squared errors to the error norm but not to the count it
/// averages over (`Layout::quadratures`): on scenes where the ledger does not change the early
/// end, a run takes at least the steps it takes without the ledger (a plain mean over all states
/// took fewer: 817 against 853 evaluations on hydraulic dt70, and a coarser motion) and at most
/// a few per cent more. Where the forces change while the states do not, the quadratures still
/// limit the step (`energy_ledger_closes_for_each_module`, hydraulic with dry and plane
/// friction: both bodies held at the first contact).
#[test]
fn the_ledger_barely_changes_the_steps() {
    let cases = [
        ("hydraulic dt70", paper("paper-hydraulic-dt70")),
        ("bistable dt70", paper("paper-bistable-dt70")),
        (
            "steel stops",
            with(
                paper("paper-hydraulic-dt70"),
                &[("stops.stiffness", "1e11")],
            ),
        ),
    ];
    for (name, s) in cases {
        let on = run(&s);
        let off = run(&with(s, &[("energy.ledger", "false")]));
        let (e_on, e_off) = (on.summary.stats.rhs_evals, off.summary.stats.rhs_evals);
        assert!(
            e_on >= e_off && (e_on as f64) <= 1.03 * e_off as f64,
            "{name}: {e_on} evaluations with the ledger, {e_off} without"
        );
        let (v_on, v_off) = (
            on.summary.object_final_velocity.unwrap(),
            off.summary.object_final_velocity.unwrap(),
        );
        assert!(
            (v_on - v_off).abs() < 1e-6,
            "{name}: {v_on} against {v_off}"
        );
    }
}

#[test]
fn absent_parts_add_no_state() {
    let l = |sets: &[(&str, &str)]| Layout::of(&with(Scene::default(), sets)).n;
    assert_eq!(l(&[("module", "rigid"), ("energy.ledger", "false")]), 2);
    assert_eq!(
        l(&[("object.enabled", "false"), ("energy.ledger", "false")]),
        2
    );
    assert_eq!(l(&[("energy.ledger", "false")]), 4);
    // the ledger: + the work and the sum of what the orifice, friction and contacts dissipate
    assert_eq!(l(&[]), 6);
    assert_eq!(l(&[("module", "bistable")]), 6);
    assert_eq!(l(&[("module", "rigid")]), 4);
    // the rigid flange alone dissipates nothing: the work only
    assert_eq!(l(&[("module", "rigid"), ("object.enabled", "false")]), 1);
    // plane friction: + int F_c dt (its dissipation goes into the ledger's one state)
    assert_eq!(l(&[("object.plane_friction", "0.3")]), 7);
    // The quadratures are the ledger's states and int F_c dt, none when they are all there is.
    let q = |sets: &[(&str, &str)]| Layout::of(&with(Scene::default(), sets)).quadratures();
    assert_eq!(q(&[]), 2);
    assert_eq!(q(&[("energy.ledger", "false")]), 0);
    assert_eq!(q(&[("object.plane_friction", "0.3")]), 3);
    assert_eq!(
        q(&[("object.plane_friction", "0.3"), ("energy.ledger", "false")]),
        1
    );
    assert_eq!(q(&[("module", "rigid"), ("object.enabled", "false")]), 0);
}

#[test]
fn robot_impulse_is_the_integral_of_f_r() {
    for name in ["paper-hydraulic-dt70", "paper-bistable-dt10", "paper-rigid"] {
        let s = tight(with(paper(name), &[("object.plane_friction", "0.2")]));
        for s in [paper(name), s] {
            let r = run_traj(&tight(s), 1e-5);
            let pts = &r.trajectory.as_ref().unwrap().points;
            let mut j = 0.0;
            for w in pts.windows(2) {
                j += 0.5 * (w[0].f_r + w[1].f_r) * (w[1].t - w[0].t);
            }
            // trapezoids over jumps of F_r at the rigid kinks are exact only up to their width
            assert!(
                close(j, r.summary.robot_impulse, 1e-4, 1e-6),
                "{name}: {j} vs {}",
                r.summary.robot_impulse
            );
        }
    }
}

#[test]
fn event_log_and_trajectory_are_consistent() {
    let r = run_traj(&paper("paper-hydraulic-dt70"), 1e-3);
    let names: Vec<&str> = r.events.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "object_contact_begin",
            "forward_stop_end",
            "sensor",
            "brake",
            "object_contact_end",
            "forward_stop_begin",
            "early_end",
            "robot_stopped"
        ]
    );
    assert!(r.events.windows(2).all(|w| w[0].t <= w[1].t));
    let sensor = &r.events[2];
    assert!((sensor.point.s - 1.5e-3).abs() < 1e-12);
    let brake = &r.events[3];
    assert!(close(brake.t, sensor.t + 0.070, 1e-14, 0.0));
    assert_eq!(r.summary.t_brake, Some(brake.t));
    let stop = &r.events[7];
    assert!(close(stop.t, brake.t + 0.1, 1e-14, 0.0) && stop.point.v_r == 0.0);
    let pts = &r.trajectory.as_ref().unwrap().points;
    assert!(pts.windows(2).all(|w| w[0].t <= w[1].t));
    assert_eq!(pts.first().unwrap().t, 0.0);
    assert_eq!(pts.last().unwrap().t, 0.3);
    // every uniform sample is there
    for k in 0..300 {
        let t = k as f64 * 1e-3;
        assert!(pts.iter().any(|p| (p.t - t).abs() < 1e-12), "sample {t}");
    }
    // quantities a scene does not have are NaN
    let r = run_traj(&with(paper("paper-rigid"), &[]), 1e-2);
    assert!(r.trajectory.unwrap().points.iter().all(|p| p.p1.is_nan()));
    assert_eq!(r.summary.max_gas_pressure, None);
}

/// `docs/model.md`, "Compressible liquid": the richer hydraulic model (compressible liquid, `p_m` a
/// state) agrees with the lumped one over the impact, costs far more steps, and an explicit method
/// finds it stiff.
#[test]
fn compressible_liquid_agrees_with_the_lumped_model_and_is_stiff() {
    let lumped = with(paper("paper-hydraulic-dt70"), &[("t_end", "0.02")]);
    // under dp5: the explicit method pays for the stiffness, and says so (below)
    let rich = with(
        lumped.clone(),
        &[
            ("hydraulic.bulk_modulus", "1.5e9"),
            ("solver.method", "dp5"),
        ],
    );
    assert_eq!(Layout::of(&lumped).n + 3, Layout::of(&rich).n);
    let a = run(&lumped).summary;
    let (r, ledger) = cushion_model::simulate_with_ledger(&rich, &RunOptions::default());
    let b = r.summary;
    assert_eq!(b.status, RunStatus::Ok, "{}", b.message);
    assert!(
        close(a.peak_robot_force, b.peak_robot_force, 1e-3, 0.0),
        "{} vs {}",
        a.peak_robot_force,
        b.peak_robot_force
    );
    assert!(close(a.peak_contact_force, b.peak_contact_force, 1e-3, 0.0));
    assert!(close(a.max_stroke, b.max_stroke, 1e-4, 0.0));
    assert!(close(
        a.max_gas_pressure.unwrap(),
        b.max_gas_pressure.unwrap(),
        1e-4,
        0.0
    ));
    assert_eq!(a.t_detect.is_some(), b.t_detect.is_some());
    assert!(close(a.t_detect.unwrap(), b.t_detect.unwrap(), 1e-4, 0.0));
    // the ledger (with the liquid's compression energy) still closes
    let l = ledger.unwrap();
    assert!(l.residual < 1e-6, "{l:?}");
    // an explicit method pays for the stiffness, and says so
    assert!(b.stats.stiff && !a.stats.stiff);
    assert!(
        b.stats.rhs_evals > 100 * a.stats.rhs_evals,
        "{} vs {}",
        b.stats.rhs_evals,
        a.stats.rhs_evals
    );
    let stop = simulate(
        &with(rich, &[("solver.stiffness", "stop")]),
        &RunOptions::default(),
    )
    .summary;
    assert_eq!(stop.status, RunStatus::Stiff);
}
