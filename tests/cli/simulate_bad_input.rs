//! Bad input to `cushion simulate`: exit status 2, one message on stderr naming the key (and
//! the value), nothing on stdout, no output file, never a panic.

use std::path::Path;
use std::process::Command;

/// Run `cushion simulate ARGS --csv --mcap --plot` into a fresh directory and check the
/// bad-input contract; returns the message.
fn rejected(args: &[&str], must_name: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (csv, mcap, svg) = (out("t.csv"), out("t.mcap"), out("f.svg"));
    let o = Command::new(env!("CARGO_BIN_EXE_cushion"))
        .arg("simulate")
        .args(args)
        .args(["--json", "--csv", &csv, "--mcap", &mcap, "--plot", &svg])
        .output()
        .expect("run cushion");
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "args {args:?}: stderr {stderr}");
    assert!(
        o.stdout.is_empty(),
        "args {args:?}: stdout {}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "one message, got:\n{stderr}"
    );
    for text in must_name {
        assert!(
            stderr.contains(text),
            "args {args:?}: message does not name `{text}`: {stderr}"
        );
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "args {args:?}: files were written"
    );
    stderr
}

#[test]
fn negative_object_mass() {
    rejected(&["--set", "object.mass=-0.5"], &["object.mass", "-0.5"]);
}

#[test]
fn zero_tool_mass() {
    rejected(&["--set", "tool.mass=0"], &["tool.mass"]);
}

#[test]
fn orifice_not_smaller_than_piston() {
    rejected(
        &["--set", "hydraulic.orifice_radius=0.02"],
        &["orifice_radius"],
    );
    rejected(
        &["--set", "hydraulic.orifice_radius=0.03"],
        &["orifice_radius", "0.03"],
    );
}

#[test]
fn gas_volume_reaching_zero_in_the_stroke() {
    // A_p * L = pi * 0.02^2 * 0.023 = 2.89e-5 m^3 > 2e-5 m^3.
    rejected(&["--set", "hydraulic.gas_volume=2e-5"], &["gas_volume"]);
}

#[test]
fn sensor_threshold_outside_the_stroke() {
    rejected(
        &["--set", "tool.sensor_threshold=0.03"],
        &["tool.sensor_threshold", "0.03"],
    );
    rejected(
        &["--set", "tool.sensor_threshold=-0.001"],
        &["tool.sensor_threshold"],
    );
}

#[test]
fn nan_and_infinite_values() {
    rejected(&["--set", "robot.dead_time=nan"], &["robot.dead_time"]);
    rejected(
        &["--set", "robot.approach_speed=inf"],
        &["robot.approach_speed"],
    );
    rejected(&["--set", "object.mass=-inf"], &["object.mass"]);
}

#[test]
fn finite_values_that_overflow_the_bistable_element() {
    // a spring so stiff that its preload equilibrium, as the engine finds it, has an infinite
    // force, and a span whose square is beyond the largest double: refused before the run, by
    // name
    rejected(
        &[
            "--set",
            "module=bistable",
            "--set",
            "bistable.spring_stiffness=1e300",
        ],
        &["bistable.spring_stiffness", "1e300", "finite"],
    );
    rejected(
        &[
            "--set",
            "module=bistable",
            "--set",
            "bistable.half_span=1e200",
        ],
        &["bistable.half_span", "1e200", "finite"],
    );
    // both stiffnesses set the preload's depth: the one further from its default is named
    rejected(
        &[
            "--set",
            "module=bistable",
            "--set",
            "bistable.spring_stiffness=1e200",
            "--set",
            "stops.stiffness=1e-200",
        ],
        &[
            "`stops.stiffness` = 1e-200",
            "bistable.spring_stiffness = 1e200",
            "larger",
        ],
    );
}

#[test]
fn tolerance_out_of_range() {
    // no step meets rtol <= 10 eps; rtol >= 1 asks for no digit
    for v in ["1e-300", "2e-15", "1", "1e30", "-1e-6", "0"] {
        let set = format!("solver.rtol={v}");
        rejected(&["--set", &set], &["solver.rtol", "(10 eps"]);
    }
}

#[test]
fn unknown_key() {
    rejected(&["--set", "robot.dead_tme=0.01"], &["robot.dead_tme"]);
    rejected(&["--set", "dead_time=0.01"], &["dead_time"]);
}

#[test]
fn wrong_type() {
    rejected(
        &["--set", "robot.dead_time=fast"],
        &["robot.dead_time", "fast"],
    );
    rejected(&["--set", "module=3"], &["module"]);
    rejected(&["--set", "module=pneumatic"], &["module", "pneumatic"]);
}

#[test]
fn set_without_equals() {
    rejected(
        &["--set", "robot.dead_time"],
        &["robot.dead_time", "KEY=VALUE"],
    );
}

#[test]
fn unreadable_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-scene.toml");
    rejected(&[missing.to_str().unwrap()], &["no-such-scene.toml"]);
}

fn scene_file(text: &str) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap().to_string();
    (dir, p)
}

#[test]
fn bad_scene_files() {
    let (_d, p) = scene_file("[robot]\ndead_time = \"fast\"\n");
    rejected(&[&p], &["dead_time"]);
    let (_d, p) = scene_file("[robot]\ndead_tme = 0.01\n");
    rejected(&[&p], &["dead_tme"]);
    let (_d, p) = scene_file("[object]\nmass = -1.0\n");
    rejected(&[&p], &["object.mass"]);
    let (_d, p) = scene_file("module = \n");
    rejected(&[&p], &["scene.toml"]);
}

#[test]
fn output_in_a_missing_directory() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("missing").join("t.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_cushion"))
        .args(["simulate", "--csv", bad.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--csv"));
    assert!(!Path::new(&bad).exists());
}
