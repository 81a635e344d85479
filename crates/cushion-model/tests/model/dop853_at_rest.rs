//! DOP853 where a stiff mode is at rest: a tool pressed onto a soft end-stop by a strong gas
//! preload, or held there by dry friction. No error estimate limits the steps there, so DOP853
//! steps far past its stability boundary (`h |lambda|` 390 to 1,000 against 6.39), and the
//! states its dense output gives inside such a step are amplified rounding. Three of 2,000 wide
//! random scenes (`lab/studies`: `wide_scenes 2000 --method dop853`, scenes in `tests/scenes/`) came
//! out wrong through it before the loop took such steps again (`cushion-ode`, `step_guard.rs`: the
//! run's first step counts as a jump for the stability guard; `events.rs`, "Crossings on a
//! dense output that is not stable"): a peak robot force of 370 N where the true one is 4e-10
//! N, one of 483 N against 10.8 N with the object's final speed 3.1e-3 m/s off, and a
//! stick-slip chattering at spurious crossings until the step limit. Each is checked against
//! the same scene under DOPRI5 at rtol 1e-11.

use cushion_model::{simulate, RunOptions, RunStatus, Summary};

use crate::common::{kept_scene, reference};

/// The scene under `method` (with a step limit), and the reference under DOPRI5 at rtol 1e-11.
fn run_and_reference(name: &str, method: &str) -> (Summary, Summary) {
    let mut s = kept_scene(name, &[("solver.method", method)]);
    // the chattering run took the default million steps; a working run takes under 2,000
    s.solver.max_steps = 20_000;
    let r = simulate(&s, &RunOptions::default()).summary;
    assert_eq!(r.status, RunStatus::Ok, "{name}: {}", r.message);
    (r, reference(kept_scene(name, &[])))
}

#[test]
fn dop853_starting_at_rest_on_a_stiff_stop() {
    // No object; the tool starts pressed 38 mm into a soft stop (27 kN/m^1.5) by 222 kPa of
    // gas, a stiff and strongly damped mode at rest. rtol 4.6e-7. The first step was 85 ms
    // long at `h |lambda|` 392; the peak sampler's search on it found 370 N.
    let (r, reference) = run_and_reference("wide-1772", "dop853");
    println!(
        "peak robot force {:.2e} N (reference {:.2e}), max stroke {:.10} (reference {:.10})",
        r.peak_robot_force, reference.peak_robot_force, r.max_stroke, reference.max_stroke
    );
    assert!(r.peak_robot_force.abs() < 1e-6, "{}", r.peak_robot_force);
    let stroke = (r.max_stroke - reference.max_stroke).abs() / reference.max_stroke.abs();
    assert!(stroke < 1e-6, "max stroke {stroke:.1e} off");
}

#[test]
fn dop853_finds_no_contact_in_an_unstable_dense_output() {
    // The tool starts pressed 23 mm into a soft stop by 431 kPa of gas; rtol 1e-5. The first
    // step ran 108 ms at `h |lambda|` 999, and the event scan found a stop contact ending
    // 0.13 ms into it, on its dense output: the state there sent the tool back at 0.65 m/s.
    let (r, reference) = run_and_reference("wide-294", "dop853");
    let force = (r.peak_robot_force - reference.peak_robot_force).abs();
    let speed = (r.object_final_velocity.unwrap() - reference.object_final_velocity.unwrap()).abs();
    println!(
        "peak robot force {:.4} N (reference {:.4}), object final speed {speed:.1e} m/s off",
        r.peak_robot_force, reference.peak_robot_force
    );
    assert!(
        force < 1e-3 * reference.peak_robot_force.abs(),
        "{force:.2e} N off"
    );
    assert!(speed < 1e-6, "object final speed {speed:.1e} m/s off");
}

#[test]
fn dop853_does_not_chatter_on_an_unstable_dense_output() {
    // Dry friction (0.24 N) on the tool, plane friction under the object, a stiff stop (2.3e7
    // N/m^1.5); rtol 3.5e-4. The tool sticks and slips; on steps at `h |lambda|` 5 to 6, past
    // the dense output's boundary (5.0), the scan found a slip or stick at every step, 20 ns
    // apart, up to the step limit, with the object's final speed 0.52 m/s off.
    let (r, reference) = run_and_reference("wide-1764", "dop853");
    let speed = (r.object_final_velocity.unwrap() - reference.object_final_velocity.unwrap()).abs();
    let impulse = (r.robot_impulse - reference.robot_impulse).abs();
    println!("object final speed {speed:.1e} m/s off, robot impulse {impulse:.1e} N s off");
    assert!(speed < 1e-4, "object final speed {speed:.1e} m/s off");
    assert!(impulse < 1e-4, "robot impulse {impulse:.1e} N s off");
}
