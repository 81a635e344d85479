//! Whole runs that end early (the robot stands or cruises on with nothing left to change, or
//! the tool rings on its stop in closed form) against the same runs integrated to `t_end`.

use cushion_model::{Module, RunResult};

use crate::common::whole_runs::*;

#[test]
fn early_end_equals_running_to_t_end() {
    let cases = [
        with(paper("paper-hydraulic-dt70"), &[("t_end", "1.5")]),
        with(
            paper("paper-hydraulic-dt10"),
            &[("t_end", "1.5"), ("object.plane_friction", "0.3")],
        ),
        with(paper("paper-rigid"), &[]),
        with(
            paper("paper-bistable-dt10"),
            &[("t_end", "1.5"), ("tool.dry_friction", "0.5")],
        ),
    ];
    for s in cases {
        // the settled early end alone (the ringing tail has its own test)
        let s = with(s, &[("solver.ringing_tail", "false")]);
        let early = run(&s);
        let full = run(&with(s.clone(), &[("solver.early_end", "false")]));
        let e = early.events.iter().find(|e| e.name == "early_end");
        assert!(e.is_some(), "{:?}: no early end", s.module);
        assert!(early.summary.stats.steps < full.summary.stats.steps);
        assert_same(
            &early.summary,
            &full.summary,
            1e-6,
            &format!("{:?}", s.module),
        );
        assert!(close(
            early.summary.energy_residual.unwrap(),
            full.summary.energy_residual.unwrap(),
            1e-3,
            1e-9
        ));
        assert_eq!(early.summary.t_brake, full.summary.t_brake);
    }
}

#[test]
fn early_end_while_the_robot_cruises_on() {
    // The robot never brakes inside the run: its sensor never switches (a gas preload too strong
    // for the object to press the tool in, or nothing to hit), or the dead time ends after
    // t_end. Once the object is gone and the tool rests on its stop (`src/early_end/riding.rs`), rings there
    // in closed form, or is stuck, the run ends; its summary is the full run's at a tight
    // tolerance, and the tool rides on with the robot.
    let strong_gas = with(
        paper("paper-hydraulic-dt70"),
        &[
            ("hydraulic.gas_pressure", "53500"),
            ("hydraulic.orifice_radius", "0.004"),
            ("object.mass", "0.42"),
        ],
    );
    let no_object = [("object.enabled", "false")];
    let cases = [
        ("strong gas preload", strong_gas),
        (
            "hydraulic, no object",
            with(paper("paper-hydraulic-dt70"), &no_object),
        ),
        (
            "bistable, no object",
            with(paper("paper-bistable-dt70"), &no_object),
        ),
        ("rigid, no object", with(paper("paper-rigid"), &no_object)),
        (
            "brake after t_end",
            with(
                paper("paper-hydraulic-dt70"),
                &[("robot.dead_time", "0.35")],
            ),
        ),
        (
            "stuck tool",
            with(
                paper("paper-hydraulic-dt70"),
                &[("object.enabled", "false"), ("tool.dry_friction", "2.0")],
            ),
        ),
    ];
    for (what, s) in cases {
        // Under dp5: the saving is the explicit method's, whose steps a tool resting on its stop
        // holds at the stability limit to t_end (auto, the default, switches to Rodas there).
        let s = with(s, &[("solver.method", "dp5")]);
        let early = run_traj(&s, 1e-3);
        assert!(
            early.events.iter().any(|e| e.name == "early_end"),
            "{what}: no early end"
        );
        let full = run(&with(s.clone(), &[("solver.early_end", "false")]));
        let reference = run_traj(
            &tight(with(s.clone(), &[("solver.early_end", "false")])),
            0.1,
        );
        let (a, b) = (&early.summary, &reference.summary);
        assert!(
            3 * a.stats.steps <= 2 * full.summary.stats.steps,
            "{what}: {} vs {} steps",
            a.stats.steps,
            full.summary.stats.steps
        );
        // the integration error of rtol 1e-6 (peaks: ~2e-6), and the robot impulse to the
        // tolerance's momentum scale rtol (m_t + m_p) v_max
        assert_same(a, b, 1e-5, what);
        assert!(
            close(a.robot_impulse, b.robot_impulse, 0.0, 3e-7),
            "{what}: {} vs {}",
            a.robot_impulse,
            b.robot_impulse
        );
        assert_eq!(a.t_brake, None, "{what}");
        assert_eq!(a.t_detect.is_some(), b.t_detect.is_some(), "{what}");
        assert_eq!(
            (a.forward_stop_impacts, a.back_stop_impacts),
            (b.forward_stop_impacts, b.back_stop_impacts),
            "{what}"
        );
        assert!(
            close(a.energy_residual.unwrap(), 0.0, 0.0, 1e-5),
            "{what}: residual {:?}",
            a.energy_residual
        );
        // at t_end the tool moves with the robot, at the stroke and speed of the reference run
        let pts = early.trajectory.unwrap().points;
        let last = pts.last().unwrap();
        assert_eq!(last.t, s.t_end, "{what}");
        if s.module != Module::Rigid {
            let end = reference
                .trajectory
                .as_ref()
                .unwrap()
                .points
                .last()
                .copied()
                .unwrap();
            assert!(
                close(last.v_t, end.v_t, 0.0, 1e-6) && close(last.s, end.s, 0.0, 1e-8),
                "{what}: {last:?} vs {end:?}"
            );
        }
    }
}

#[test]
fn a_cruising_robot_does_not_end_early_before_an_object_it_will_reach() {
    // plane friction stops the object; the robot, whose sensor the strong gas preload keeps
    // from switching, cruises into it again: no early end until the object is out of reach
    // for good, and the summary is the full run's to the bit
    let s = with(
        paper("paper-hydraulic-dt70"),
        &[
            ("hydraulic.gas_pressure", "53500"),
            ("object.plane_friction", "0.4"),
        ],
    );
    let early = run(&s);
    let full = run(&with(s.clone(), &[("solver.early_end", "false")]));
    assert!(early.summary.t_detect.is_none());
    assert!(early.summary.object_impacts > 1, "{:?}", early.summary);
    assert!(!early.events.iter().any(|e| e.name == "early_end"));
    assert_eq!(early.summary, full.summary);
}

/// The same events at the same times (to 1 ns), but for the early end itself.
fn assert_same_events(tail: &RunResult, full: &RunResult, what: &str) {
    let names = |r: &RunResult| -> Vec<(String, f64)> {
        r.events
            .iter()
            .filter(|e| e.name != "early_end")
            .map(|e| (e.name.clone(), e.t))
            .collect()
    };
    let (na, nb) = (names(tail), names(full));
    assert_eq!(na.len(), nb.len(), "{what}: {na:?} vs {nb:?}");
    for ((x, tx), (y, ty)) in na.iter().zip(nb.iter()) {
        assert!(
            x == y && (tx - ty).abs() <= 1e-9,
            "{what}: {x} {tx} vs {y} {ty}"
        );
    }
}

#[test]
fn ringing_tail_equals_running_to_t_end() {
    // The tool's ringing on its stop, written in closed form once it is small, against the
    // integrated ringing: same counts and events, summary within the tolerance (robot impulse
    // to 1e-6 N s, the momentum scale times rtol), a third of the steps or fewer saved.
    let cases = [
        paper("paper-hydraulic-dt70"),
        paper("paper-hydraulic-dt10"),
        paper("paper-bistable-dt70"),
        paper("paper-bistable-dt10"),
        with(
            paper("paper-hydraulic-dt70"),
            &[("hydraulic.gas_pressure", "5000")],
        ),
        with(
            paper("paper-hydraulic-dt70"),
            &[("robot.brake_deceleration", "25")],
        ),
        // the tail begins while the robot still cruises: the brake happens inside it
        with(
            paper("paper-hydraulic-dt70"),
            &[
                ("robot.dead_time", "0.15"),
                ("robot.brake_deceleration", "2"),
            ],
        ),
    ];
    for s in cases {
        let what = format!(
            "{:?} gas {} brake {}",
            s.module, s.hydraulic.gas_pressure, s.robot.brake_deceleration
        );
        let tail = run_traj(&s, 1e-3);
        let full = run_traj(&with(s.clone(), &[("solver.ringing_tail", "false")]), 1e-3);
        let te = event_time(&tail, "early_end");
        assert!(te.is_some(), "{what}: no ringing tail");
        let (a, b) = (&tail.summary, &full.summary);
        assert!(
            3 * a.stats.steps <= 2 * b.stats.steps,
            "{what}: {} vs {} steps",
            a.stats.steps,
            b.stats.steps
        );
        assert_same(a, b, 1e-6, &what);
        assert!(
            close(a.t_brake.unwrap(), b.t_brake.unwrap(), 1e-12, 0.0),
            "{what}"
        );
        assert_eq!(
            (
                a.object_impacts,
                a.forward_stop_impacts,
                a.back_stop_impacts,
                a.back_stop_hit
            ),
            (
                b.object_impacts,
                b.forward_stop_impacts,
                b.back_stop_impacts,
                b.back_stop_hit
            ),
            "{what}"
        );
        // the ledger over the tail is computed from the force law along the closed form, and the
        // tail is taken only where its energy error is predicted within 3 rtol of the ledger's
        // scale: its residual is then as small as the integrated run's (at most 4.2e-6, the
        // bistable scene's, whose integrated run has 4.0e-6)
        assert!(
            a.energy_residual.unwrap() <= 5.0 * s.solver.rtol,
            "{what}: {:?}",
            a.energy_residual
        );
        assert!(close(
            a.max_gas_pressure.unwrap_or(0.0),
            b.max_gas_pressure.unwrap_or(0.0),
            1e-9,
            0.0
        ));
        // the same events (the robot's stop inside the tail included), at the same times
        assert_same_events(&tail, &full, &what);
        // the uniform samples after the early end follow the integrated ringing to 1 % of the
        // stop's depth (stroke), of the depth times 1000 /s (tool speed; the ringing is at
        // ~500 rad/s) and 2 % of the stop's preload force (force on the robot)
        let pa = &tail.trajectory.unwrap().points;
        let pb = &full.trajectory.unwrap().points;
        let mut compared = 0;
        for p in pa.iter().filter(|p| p.t > te.unwrap()) {
            if let Some(q) = pb.iter().find(|q| q.t == p.t) {
                let depth = if q.s < 0.0 {
                    -q.s
                } else {
                    q.s - s.stops.stroke
                };
                let preload = s.stops.stiffness * depth.abs().powf(1.5);
                assert!(
                    (p.s - q.s).abs() < 0.01 * depth.abs()
                        && (p.v_t - q.v_t).abs() < 10.0 * depth.abs()
                        && (p.f_r - q.f_r).abs() < 0.02 * preload,
                    "{what}: t = {}: {p:?} vs {q:?}",
                    p.t
                );
                compared += 1;
            }
        }
        assert!(compared > 50, "{what}: {compared} samples");
        assert_eq!(pa.last().unwrap().t, s.t_end);
    }
}

#[test]
fn a_tail_up_to_the_robots_stop_equals_running_through_it() {
    // At tight tolerances the robot's stop shakes the tool too much for the closed form (the
    // new equilibrium lies further from the ringing than the amplitude limit allows), so the
    // ringing is written in closed form only while the robot brakes, and integrated again from
    // its stop (`RingingTail::resume`). Against the same runs integrated throughout: the same
    // summary within the tolerance, events and counts; the energy residual within 5 rtol; no
    // step inside the closed form's stretch; its uniform samples on the integrated ringing
    // to 1 % of the stop's depth.
    let robot_stop = 0.174_580_391;
    for (method, rtol) in [("dp5", 1e-7), ("dop853", 1e-7), ("dp5", 3e-8)] {
        let s = with(
            paper("paper-hydraulic-dt70"),
            &[
                ("solver.method", method),
                ("solver.rtol", &rtol.to_string()),
                ("solver.atol", &(rtol / 1000.0).to_string()),
            ],
        );
        let what = format!("{method} rtol {rtol}");
        let tail = run_traj(&s, 1e-3);
        let full = run_traj(&with(s.clone(), &[("solver.ringing_tail", "false")]), 1e-3);
        let (a, b) = (&tail.summary, &full.summary);
        assert_same(a, b, 10.0 * rtol, &what);
        // the tail's admission predicts its impulse error within rtol of the momentum scale;
        // the prediction is good to a factor of two or so (the tail taken after the robot's
        // stop, at 3e-8, leaves 1.25 of it)
        let momentum_scale = (s.tool.mass + s.object.mass) * s.robot.approach_speed;
        assert!(
            (a.robot_impulse - b.robot_impulse).abs() <= 2.0 * rtol * momentum_scale,
            "{what}: impulse {} vs {}",
            a.robot_impulse,
            b.robot_impulse
        );
        assert!(
            a.energy_residual.unwrap().abs() <= 5.0 * rtol,
            "{what}: {:?}",
            a.energy_residual
        );
        assert_same_events(&tail, &full, &what);
        // before the robot's stop, a stretch of at least a period of the ringing (12.8 ms)
        // with only uniform samples (every 1 ms) in the tail's run, where the integrated run
        // has its step ends too
        let pa = &tail.trajectory.unwrap().points;
        let pb = &full.trajectory.unwrap().points;
        let off_grid =
            |p: &&cushion_model::TrajectoryPoint| ((p.t / 1e-3).round() * 1e-3 - p.t).abs() > 1e-12;
        let last_step = pa
            .iter()
            .filter(|p| p.t < robot_stop - 1e-6)
            .filter(off_grid)
            .fold(0.0_f64, |t, p| t.max(p.t));
        assert!(
            robot_stop - last_step > 0.0128,
            "{what}: last step at {last_step}"
        );
        let window =
            |p: &&cushion_model::TrajectoryPoint| p.t > last_step && p.t < robot_stop - 1e-6;
        assert!(
            pb.iter().filter(window).filter(off_grid).count() > 5,
            "{what}"
        );
        let mut compared = 0;
        for p in pa.iter().filter(window) {
            let q = pb.iter().find(|q| q.t == p.t).expect("the same sample");
            assert!(
                (p.s - q.s).abs() < 0.01 * q.s.abs(),
                "{what}: t = {}: {p:?} vs {q:?}",
                p.t
            );
            compared += 1;
        }
        assert!(compared >= 12, "{what}: {compared} samples");
    }
}

#[test]
fn ringing_tail_is_not_taken_where_it_cannot_hold() {
    // dry friction (stick-slip) and the rigid module keep integrating; so does a tight
    // tolerance until the ringing is small enough for it
    for sets in [
        vec![("tool.dry_friction", "0.5")],
        vec![("module", "rigid")],
    ] {
        let s = with(paper("paper-hydraulic-dt70"), &sets);
        let on = run(&s);
        let off = run(&with(s.clone(), &[("solver.ringing_tail", "false")]));
        assert_eq!(on.summary.stats, off.summary.stats, "{sets:?}");
    }
    let loose = run(&paper("paper-hydraulic-dt70"));
    let tight = run(&tight(paper("paper-hydraulic-dt70")));
    let te = |r: &RunResult| event_time(r, "early_end");
    // a tighter tolerance takes the tail later, or not at all
    let (t_loose, t_tight) = (te(&loose).unwrap(), te(&tight));
    assert!(
        t_tight.is_none_or(|t| t > t_loose + 0.02),
        "{t_tight:?} {t_loose}"
    );
}

#[test]
fn early_end_trajectory_keeps_its_uniform_samples() {
    let s = with(paper("paper-rigid"), &[]);
    let r = run_traj(&s, 1e-3);
    assert!(r.events.iter().any(|e| e.name == "early_end"));
    let pts = &r.trajectory.unwrap().points;
    let full = run_traj(&with(s, &[("solver.early_end", "false")]), 1e-3);
    let fpts = &full.trajectory.unwrap().points;
    for k in 1..300 {
        let t = k as f64 * 1e-3;
        let a = pts
            .iter()
            .find(|p| (p.t - t).abs() < 1e-12)
            .expect("sample present");
        let b = fpts.iter().find(|p| (p.t - t).abs() < 1e-12).unwrap();
        assert!(
            close(a.x_p, b.x_p, 1e-9, 1e-12) && close(a.v_p, b.v_p, 1e-9, 1e-12),
            "t = {t}: {a:?} vs {b:?}"
        );
        assert!(close(a.x_r, b.x_r, 1e-12, 1e-12) && a.f_r == b.f_r);
    }
    assert_eq!(pts.last().unwrap().t, 0.3);
}

#[test]
fn the_ledger_over_a_ringing_tail_shrinks_with_the_tolerance() {
    // The ledger's residual over a ringing tail holds the closed form's energy error against
    // the force law (`src/early_end/ledger.rs`, its tests), which the tail's admission keeps within 3 rtol of the
    // ledger's scale (`src/early_end/ringing_search.rs`, `ENERGY_ERROR`), and the integrated ledger's
    // own global error, a few rtol. On the shallowest stop of the tested scenes (5 kPa gas):
    // 6.8e-7 at rtol 1e-6, 5.2e-8 at 1e-8; without the energy test the first was 1.4e-5.
    for rtol in ["1e-6", "1e-8"] {
        let s = with(
            paper("paper-hydraulic-dt70"),
            &[("hydraulic.gas_pressure", "5000"), ("solver.rtol", rtol)],
        );
        let r = run(&s);
        assert!(
            r.events.iter().any(|e| e.name == "early_end"),
            "rtol {rtol}"
        );
        let residual = r.summary.energy_residual.unwrap();
        assert!(residual <= 8.0 * s.solver.rtol, "rtol {rtol}: {residual:e}");
    }
}
