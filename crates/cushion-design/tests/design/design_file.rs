//! Design files: a good one parses to the question it writes, and each kind of bad input is
//! refused with one message naming the table, the key, the value and what is allowed.

use std::path::{Path, PathBuf};

use cushion_design::{DesignFile, Sense};
use cushion_sweep::sweep_file::AxisValues;
use toml::Value;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sweeps/scenes")
}

/// A design file's text with the default scene: one head, then `body`.
fn parse(body: &str) -> Result<DesignFile, String> {
    DesignFile::from_str_at(body, &scenes().join("question.toml"))
}

const DESIGN: &str = r#"
[[design]]
key = "hydraulic.gas_pressure"
range = [300.0, 1e5]
scale = "log"
"#;
const FOR_ALL: &str = r#"
[[for_all]]
key = "object.mass"
range = [0.05, 1.0]
"#;
const LIMIT: &str = r#"
[[limit]]
metric = "peak_robot_force"
max = 40.0
abs = true
"#;

fn err(body: &str) -> String {
    match parse(body) {
        Ok(_) => panic!("accepted:\n{body}"),
        Err(e) => e,
    }
}

fn assert_names(e: &str, parts: &[&str]) {
    for p in parts {
        assert!(e.contains(p), "`{p}` not in the message: {e}");
    }
}

#[test]
fn a_good_file_gives_its_question() {
    let text = format!(
        r#"name = "q"
scene = "paper-hydraulic-dt70.toml"
[set]
"solver.rtol" = 1e-7
{DESIGN}
[[design]]
key = "module"
values = ["hydraulic", "bistable"]
{FOR_ALL}
[[for_all]]
key = "robot.dead_time"
values = [0.0, 0.05, 0.1]
{LIMIT}
[[limit]]
metric = "object_final_velocity"
max = 1.3
min = -0.5
[objective]
minimize = "peak_robot_force"
[search]
resolution = 0.125
tolerance = 1e-2
verify = 11
"#
    );
    let f = parse(&text).unwrap();
    assert_eq!(f.name, "q");
    assert_eq!(f.base.get("solver.rtol").unwrap(), Value::Float(1e-7));
    assert_eq!(f.base.get("robot.dead_time").unwrap(), Value::Float(0.07));
    assert_eq!(f.design.len(), 2);
    assert_eq!(
        f.design[0].values,
        AxisValues::Range {
            low: 300.0,
            high: 1e5,
            log: true
        }
    );
    assert_eq!(
        f.design[1].values,
        AxisValues::List(vec![
            Value::String("hydraulic".into()),
            Value::String("bistable".into())
        ])
    );
    assert_eq!(f.for_all[1].key, "robot.dead_time");
    assert_eq!(f.limits.len(), 2);
    assert!(f.limits[0].abs && f.limits[0].max == Some(40.0));
    assert_eq!(
        (f.limits[1].max, f.limits[1].min, f.limits[1].abs),
        (Some(1.3), Some(-0.5), false)
    );
    let o = f.objective.as_ref().unwrap();
    assert_eq!(
        (o.metric.as_str(), o.sense),
        ("peak_robot_force", Sense::Minimize)
    );
    assert_eq!(
        (f.search.resolution, f.search.tolerance, f.search.verify),
        (0.125, 1e-2, 11)
    );
    // The search sees a log range and a list of two values; targets: |force| max, speed max
    // and min (the objective shares the force's).
    let r = f.refinement().unwrap();
    assert_eq!(r.design_axes().len(), 2);
    assert_eq!(r.limits().targets().len(), 3);

    // Defaults: the file's stem as name, 1/64, 1e-3, 41.
    let f = parse(&format!("{DESIGN}{FOR_ALL}{LIMIT}")).unwrap();
    assert_eq!(f.name, "question");
    assert_eq!(
        (f.search.resolution, f.search.tolerance, f.search.verify),
        (1.0 / 64.0, 1e-3, 41)
    );
}

#[test]
fn a_key_in_design_and_in_for_all() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[for_all]]\nkey = \"hydraulic.gas_pressure\"\nrange = [1e3, 1e4]\n{LIMIT}"
    ));
    assert_names(
        &e,
        &[
            "[[for_all]] #2",
            "`hydraulic.gas_pressure`",
            "also a [[design]] axis",
        ],
    );
}

#[test]
fn a_limit_on_an_unknown_metric() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[limit]]\nmetric = \"peak_force\"\nmax = 1.0\n"
    ));
    assert_names(
        &e,
        &[
            "[[limit]] #1",
            "metric = \"peak_force\"",
            "allowed:",
            "object_final_velocity",
        ],
    );
}

#[test]
fn a_limit_on_a_metric_that_is_not_a_number() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[limit]]\nmetric = \"back_stop_hit\"\nmax = 1.0\n"
    ));
    assert_names(&e, &["[[limit]] #1", "\"back_stop_hit\"", "not a number"]);
}

#[test]
fn min_above_max() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[[limit]]\nmetric = \"max_stroke\"\nmax = 0.01\nmin = 0.02\n"
    ));
    assert_names(
        &e,
        &[
            "[[limit]] #2 (`max_stroke`)",
            "min = 0.02",
            "at most max (0.01)",
        ],
    );
}

#[test]
fn a_limit_without_bound_and_a_negative_size() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[limit]]\nmetric = \"max_stroke\"\n"
    ));
    assert_names(&e, &["[[limit]] #1 (`max_stroke`)", "max and/or min"]);
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[limit]]\nmetric = \"peak_robot_force\"\nmax = -1.0\nabs = true\n"
    ));
    assert_names(&e, &["limit.peak_robot_force.max = -1", "abs = true"]);
}

#[test]
fn an_empty_box() {
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"object.mass\"\nrange = [0.5, 0.5]\n{LIMIT}"
    ));
    assert_names(&e, &["object.mass.range = [0.5, 0.5]", "low < high"]);
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"object.mass\"\nrange = [0.5, 0.1]\n{LIMIT}"
    ));
    assert_names(
        &e,
        &[
            "[[for_all]] #1 (`object.mass`)",
            "low 0.5 is above high 0.1",
        ],
    );
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"module\"\nvalues = []\n{LIMIT}"
    ));
    assert_names(&e, &["[[for_all]] #1 (`module`)", "`values` is empty"]);
    let e = err(&format!("{DESIGN}{LIMIT}"));
    assert_names(&e, &["[[for_all]]", "none given"]);
}

#[test]
fn more_than_four_design_axes() {
    let axes: String = [
        "hydraulic.gas_pressure",
        "hydraulic.orifice_radius",
        "hydraulic.piston_radius",
        "hydraulic.gas_volume",
        "hydraulic.loss_coefficient",
    ]
    .iter()
    .map(|k| {
        let v: f64 = match *k {
            "hydraulic.gas_pressure" => 1000.0,
            "hydraulic.orifice_radius" => 0.008,
            "hydraulic.piston_radius" => 0.02,
            "hydraulic.gas_volume" => 7.63e-5,
            _ => 3.0,
        };
        format!(
            "[[design]]\nkey = \"{k}\"\nrange = [{:?}, {:?}]\n",
            v * 0.9,
            v * 1.1
        )
    })
    .collect();
    let e = err(&format!("{axes}{FOR_ALL}{LIMIT}"));
    assert_names(&e, &["[[design]]", "5 axes", "1 to 4"]);
}

#[test]
fn an_objective_on_a_metric_not_limited_or_not_numeric() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[objective]\nmaximize = \"object_travel\"\n"
    ));
    assert_names(
        &e,
        &[
            "[objective] maximize = \"object_travel\"",
            "has a [[limit]]",
        ],
    );
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[objective]\nminimize = \"status\"\n"
    ));
    assert_names(&e, &["[objective] minimize = \"status\"", "not a number"]);
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[objective]\nminimize = \"peak_robot_force\"\nmaximize = \"peak_robot_force\"\n"
    ));
    assert_names(&e, &["[objective]", "exactly one"]);
}

#[test]
fn unknown_keys_of_the_file() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[output]\nrecord = \"none\"\n"
    ));
    assert_names(&e, &["unknown key `output`", "the design file", "allowed:"]);
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[search]\nresolutoin = 0.1\n"
    ));
    assert_names(&e, &["unknown key `resolutoin`", "[search]"]);
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"object.mass\"\nlinspace = [0.1, 1.0, 5]\n{LIMIT}"
    ));
    assert_names(
        &e,
        &[
            "unknown key `linspace`",
            "[[for_all]] #1 (`object.mass`)",
            "range, scale, values",
        ],
    );
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}[[limit]]\nmetric = \"peak_robot_force\"\nmax = 1.0\nrelative = true\n"
    ));
    assert_names(&e, &["unknown key `relative`", "[[limit]] #1"]);
}

#[test]
fn scene_keys_and_values_as_a_sweep_file_checks_them() {
    let e = err(&format!(
        "[[design]]\nkey = \"hydraulic.gas_presure\"\nrange = [300.0, 1e5]\n{FOR_ALL}{LIMIT}"
    ));
    assert_names(
        &e,
        &[
            "[[design]] #1 (`hydraulic.gas_presure`)",
            "unknown scene key",
            "allowed:",
        ],
    );
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"module\"\nvalues = [\"hydraulic\", \"spring\"]\n{LIMIT}"
    ));
    assert_names(&e, &["[[for_all]] #1 (`module`)", "\"spring\""]);
    let e = err(&format!(
        "{DESIGN}[[for_all]]\nkey = \"object.mass\"\nrange = [-1.0, 1.0]\n{LIMIT}"
    ));
    assert_names(
        &e,
        &[
            "[[for_all]] #1 (`object.mass`)",
            "value -1.0",
            "object.mass",
        ],
    );
    let e = err(&format!(
        "[set]\n\"object.mass\" = 0.3\n{DESIGN}{FOR_ALL}{LIMIT}"
    ));
    assert_names(&e, &["[[for_all]] #1 (`object.mass`)", "also in [set]"]);
    let e = err(&format!(
        "[[design]]\nkey = \"hydraulic.gas_pressure\"\nrange = [0.0, 1e5]\nscale = \"log\"\n{FOR_ALL}{LIMIT}"
    ));
    assert_names(
        &e,
        &["[[design]] #1 (`hydraulic.gas_pressure`)", "log", "low > 0"],
    );
}

#[test]
fn search_settings_out_of_range() {
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[search]\nresolution = 2.0\n"
    ));
    assert_names(&e, &["[search] resolution = 2.0", "(0, 1]"]);
    let e = err(&format!("{DESIGN}{FOR_ALL}{LIMIT}[search]\nverify = 1\n"));
    assert_names(&e, &["[search] verify = 1", "from 2"]);
    let e = err(&format!(
        "{DESIGN}{FOR_ALL}{LIMIT}[search]\ntolerance = 0\n"
    ));
    assert_names(&e, &["[search] tolerance = 0", "(0, 1)"]);
}

#[test]
fn syntax_errors_name_the_line_and_files_their_path() {
    let e = err(&format!("{DESIGN}\n[[for_all]\nkey = 1\n"));
    assert_names(&e, &["TOML syntax error at line 7"]);
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("d.toml");
    std::fs::write(&p, format!("{DESIGN}{LIMIT}")).unwrap();
    let e = DesignFile::from_file(&p).unwrap_err();
    assert!(e.starts_with(&format!("{}: ", p.display())), "{e}");
    let e = DesignFile::from_file(&dir.path().join("missing.toml")).unwrap_err();
    assert!(e.contains("cannot read"), "{e}");
}
