//! An event that recurs within picoseconds of a restart. After a restart the loop first tries
//! the step that followed the same event the last time, grown as its error allowed
//! (`cushion-ode`, `restart_steps.rs`). When that first step was cut short by the next event
//! near its start, the length it taught was its whole attempt, not the part the run kept
//! (the loop, `solve.rs`, passes the kept part). Under DOPRI5 one of 20,000 wide scenes
//! (`wide_scenes 20000 4242`, a study binary of `lab/studies`) missed a stick of the tool that
//! way and came out wrong. Under Rodas two of 20,000 wide corner scenes
//! (`wide_scenes 20000 4242 --corners --method rodas`; the scenes in `tests/scenes/`)
//! then tried a first step of 13 ms, or one grown at every recurrence to 0.57 s, found the next
//! event picoseconds into it, on an event function that sits at zero to within rounding, and
//! did so again after every restart until the million-step limit. Each scene is checked
//! against itself under DOPRI5 at rtol 1e-11.

use cushion_model::{simulate, RunOptions, RunStatus, Summary};

use crate::common::{kept_scene, reference, run_ok};

/// The scene under `method` (with a step limit), and the reference under DOPRI5 at rtol 1e-11.
fn run_and_reference(name: &str, method: &str) -> (Summary, Summary) {
    // (the stiffness test is DOPRI5's; the reference keeps the scene's `warn` as well)
    let warn = ("solver.stiffness", "warn");
    let mut s = kept_scene(name, &[("solver.method", method), warn]);
    // the chattering runs took the default million steps; a working one takes under 200
    s.solver.max_steps = 20_000;
    let r = simulate(&s, &RunOptions::default()).summary;
    assert_eq!(
        r.status,
        RunStatus::Ok,
        "{name} under {method}: {}",
        r.message
    );
    (r, reference(kept_scene(name, &[warn])))
}

fn counts(s: &Summary) -> (u32, u32, u32) {
    (
        s.object_impacts,
        s.forward_stop_impacts,
        s.back_stop_impacts,
    )
}

#[test]
fn a_contact_held_at_its_release_point_does_not_stall_rodas() {
    // Bistable module, rtol 2.6e-4. The object separates from the tool at exactly
    // `k_c / chi_c` (0.157 m/s) while the tool rides at the robot's speed, so the contact's
    // Hunt-Crossley force stays at zero on both sides of its release; the release event was
    // found again 8e-13 s into each restart's first step.
    for method in ["rodas", "auto"] {
        let (r, reference) = run_and_reference("wide-4242-corner-5279", method);
        let speed =
            (r.object_final_velocity.unwrap() - reference.object_final_velocity.unwrap()).abs();
        let impulse = (r.robot_impulse - reference.robot_impulse).abs();
        println!(
            "{method}: {} steps, object final speed {speed:.1e} m/s off, robot impulse {impulse:.1e} N s off",
            r.stats.steps
        );
        assert_eq!(counts(&r), counts(&reference), "{method}");
        // rtol 2.6e-4 of speeds near 4 m/s and of an impulse near 3.6 N s
        assert!(
            speed < 1e-3,
            "{method}: object final speed {speed:.1e} m/s off"
        );
        assert!(
            impulse < 1e-3,
            "{method}: robot impulse {impulse:.1e} N s off"
        );
    }
}

#[test]
fn a_contact_that_ends_does_not_begin_again_at_once_under_rodas() {
    // Dry friction on the tool, plane friction under the object, rtol 6e-4. An object contact
    // ended, and 2e-12 s into the next step (the learned first step, 0.57 s long) the scan found
    // it beginning again, 1e-14 m deep, while the bodies separated at 1.1 mm/s. The run is a
    // chain of 17 impacts, whose times drift at this tolerance.
    let (r, reference) = run_and_reference("wide-4242-corner-19654", "rodas");
    let speed = (r.object_final_velocity.unwrap() - reference.object_final_velocity.unwrap()).abs();
    println!(
        "{} steps, impacts {:?} (reference {:?}), object final speed {speed:.1e} m/s off",
        r.stats.steps,
        counts(&r),
        counts(&reference)
    );
    assert_eq!(counts(&r), counts(&reference));
    assert!(
        speed < 0.01 * reference.object_final_velocity.unwrap(),
        "object final speed {speed:.1e} m/s off"
    );
}

#[test]
fn a_stick_after_a_recurring_slip_is_not_stepped_over() {
    // Bistable module under DOPRI5 (the default), rtol 4.5e-5: dry friction (1.1 N) on the
    // tool pushing a 73 g object across a plane with friction 0.73. The tool sticks and slips
    // again every few milliseconds. The first step after a slip, learned whole from attempts
    // cut short at the stick, grew to a millisecond and stepped over a stick: the tool then
    // slipped back through its stroke, the sensor switched at 0.228 s, and the tool hit its back
    // stop twice, where the true run never detects (its largest stroke 0.64 mm, not 23.7 mm).
    let r = run_ok(&kept_scene("wide-4242-1219", &[]));
    let reference = reference(kept_scene("wide-4242-1219", &[]));
    let stroke = (r.max_stroke - reference.max_stroke).abs() / reference.max_stroke;
    println!(
        "detected {:?} (reference {:?}), max stroke {:.4e} m (reference {:.4e})",
        r.t_detect, reference.t_detect, r.max_stroke, reference.max_stroke
    );
    assert_eq!(reference.t_detect, None);
    assert_eq!(r.t_detect, None);
    assert_eq!(counts(&r), counts(&reference));
    assert!(stroke < 1e-3, "max stroke {stroke:.1e} off");
}
