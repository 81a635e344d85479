//! Scene keys: defaults of docs/scene-keys.md, parsing, `--set`, and every bad input of issue 3
//! rejected with a message that names the key (one test each).

use cushion_model::{simulate, ConfigError, Module, RunOptions, RunStatus, Scene};

#[test]
fn defaults_are_the_documented_values() {
    let s = Scene::default();
    let expect: &[(&str, toml::Value)] = &[
        ("module", "hydraulic".into()),
        ("t_end", 0.3.into()),
        ("robot.approach_speed", 1.0.into()),
        ("robot.brake_deceleration", 10.0.into()),
        ("robot.dead_time", 0.070.into()),
        ("robot.start", "cruising".into()),
        ("robot.acceleration", 10.0.into()),
        ("tool.mass", 0.048.into()),
        ("tool.sensor_threshold", 1.5e-3.into()),
        ("tool.viscous_friction", 0.5.into()),
        ("tool.dry_friction", 0.0.into()),
        ("object.mass", 0.246.into()),
        ("object.gap", 1e-3.into()),
        ("object.contact_stiffness", 0.6e6.into()),
        ("object.contact_damping", 1.35e6.into()),
        ("object.plane_friction", 0.0.into()),
        ("stops.stroke", 0.023.into()),
        ("stops.stiffness", 0.6e6.into()),
        ("stops.damping", 1.35e6.into()),
        ("hydraulic.piston_radius", 0.020.into()),
        ("hydraulic.orifice_radius", 0.008.into()),
        ("hydraulic.loss_coefficient", 3.0.into()),
        ("hydraulic.liquid_density", 900.0.into()),
        ("hydraulic.gas_pressure", 1000.0.into()),
        ("hydraulic.gas_volume", 7.63e-5.into()),
        ("hydraulic.gas_exponent", 1.4.into()),
        ("bistable.spring_stiffness", 7022.0.into()),
        ("bistable.half_span", 0.030.into()),
        ("bistable.apex_rise", 0.0125.into()),
        ("bistable.offset", 0.001.into()),
        ("solver.method", "auto".into()),
        ("solver.rtol", 1e-6.into()),
        ("solver.atol", 1e-9.into()),
    ];
    for (k, v) in expect {
        assert_eq!(&s.get(k).unwrap(), v, "{k}");
        assert!(Scene::keys().contains(k), "{k} not in keys()");
    }
    s.validate().unwrap();
}

#[test]
fn every_key_round_trips_through_toml() {
    let mut s = Scene::default();
    s.set_from_str("module", "bistable").unwrap();
    s.set_from_str("robot.dead_time", "0.01").unwrap();
    s.set_from_str("solver.rtol", "1e-10").unwrap();
    s.set_from_str("robot.start", "rest").unwrap();
    s.set_from_str("energy.ledger", "false").unwrap();
    s.set_from_str("solver.max_steps", "1234").unwrap();
    let text = toml::to_string(&s.to_toml()).unwrap();
    let back = Scene::from_toml_str(&text).unwrap();
    assert_eq!(back, s);
    for k in Scene::keys() {
        assert_eq!(back.get(k).unwrap(), s.get(k).unwrap(), "{k}");
    }
}

#[test]
fn set_from_str_parses_toml_values_and_bare_words() {
    let mut s = Scene::default();
    s.set_from_str("module", "rigid").unwrap();
    assert_eq!(s.module, Module::Rigid);
    s.set_from_str("module", "\"bistable\"").unwrap();
    assert_eq!(s.module, Module::Bistable);
    // a float key takes an integer
    s.set_from_str("hydraulic.gas_pressure", "2000").unwrap();
    assert_eq!(s.hydraulic.gas_pressure, 2000.0);
    s.set("object.mass", &toml::Value::Integer(1)).unwrap();
    assert_eq!(s.object.mass, 1.0);
    s.set_from_str("object.enabled", "false").unwrap();
    assert!(!s.object.enabled);
}

#[test]
fn scene_file_sections_and_defaults() {
    let s = Scene::from_toml_str("module = \"rigid\"\n[robot]\ndead_time = 0.01\n").unwrap();
    assert_eq!(s.module, Module::Rigid);
    assert_eq!(s.robot.dead_time, 0.01);
    assert_eq!(s.tool.mass, 0.048);
    // dotted keys work too
    let s = Scene::from_toml_str("robot.dead_time = 0.02\n").unwrap();
    assert_eq!(s.robot.dead_time, 0.02);
}

#[test]
fn shipped_scenes_parse_and_validate() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sweeps/scenes");
    for name in [
        "paper-hydraulic-dt70",
        "paper-hydraulic-dt10",
        "paper-bistable-dt70",
        "paper-bistable-dt10",
        "paper-rigid",
    ] {
        let s = Scene::from_file(&dir.join(format!("{name}.toml"))).unwrap();
        s.validate().unwrap();
    }
}

fn invalid_after(key: &str, text: &str) -> String {
    invalid_in(&[], key, text)
}

/// [`invalid_after`] in a scene with the parts `sets` give it.
fn invalid_in(sets: &[(&str, &str)], key: &str, text: &str) -> String {
    let mut s = Scene::default();
    for (k, v) in sets {
        s.set_from_str(k, v).unwrap();
    }
    s.set_from_str(key, text).unwrap();
    let err = s.validate().unwrap_err();
    assert_eq!(err.key(), Some(key), "{err}");
    let msg = err.to_string();
    assert!(msg.contains(key), "{msg}");
    // simulate never panics on it: status invalid with the same message
    let r = simulate(&s, &RunOptions::default());
    assert_eq!(r.summary.status, RunStatus::Invalid);
    assert_eq!(r.summary.message, msg);
    msg
}

#[test]
fn rejects_negative_tool_mass() {
    let m = invalid_after("tool.mass", "-0.1");
    assert!(m.contains("-0.1") && m.contains("> 0"), "{m}");
}

#[test]
fn rejects_zero_object_mass() {
    let m = invalid_after("object.mass", "0");
    assert!(m.contains("> 0"), "{m}");
}

#[test]
fn rejects_orifice_not_smaller_than_piston() {
    let m = invalid_after("hydraulic.orifice_radius", "0.02");
    assert!(m.contains("0.02") && m.contains("piston"), "{m}");
}

#[test]
fn rejects_gas_volume_reaching_zero_inside_stroke() {
    // A_p L = pi 0.02^2 0.023 = 2.89e-5 m^3
    let m = invalid_after("hydraulic.gas_volume", "2e-5");
    assert!(m.contains("0.00002") || m.contains("2e-5"), "{m}");
    assert!(m.contains("stroke"), "{m}");
}

#[test]
fn rejects_sensor_threshold_outside_stroke() {
    let m = invalid_after("tool.sensor_threshold", "0.03");
    assert!(m.contains("0.03") && m.contains("stroke"), "{m}");
    invalid_after("tool.sensor_threshold", "0");
    invalid_after("tool.sensor_threshold", "-1e-3");
}

#[test]
fn rejects_nan() {
    let m = invalid_after("robot.dead_time", "nan");
    assert!(m.contains("nan") && m.contains("finite"), "{m}");
}

#[test]
fn rejects_infinity() {
    let m = invalid_after("object.mass", "inf");
    assert!(m.contains("inf") && m.contains("finite"), "{m}");
}

#[test]
fn rejects_negative_dead_time() {
    let m = invalid_after("robot.dead_time", "-0.01");
    assert!(m.contains(">= 0"), "{m}");
}

#[test]
fn rejects_non_positive_tolerance() {
    invalid_after("solver.rtol", "0");
    invalid_after("solver.atol", "-1e-9");
}

#[test]
fn rejects_unknown_key() {
    let mut s = Scene::default();
    let e = s.set_from_str("robot.dead_tim", "0.01").unwrap_err();
    assert!(matches!(e, ConfigError::UnknownKey { .. }));
    let m = e.to_string();
    assert!(
        m.contains("robot.dead_tim") && m.contains("robot.dead_time"),
        "{m}"
    );
    let e = Scene::from_toml_str("[tool]\nmas = 0.1\n").unwrap_err();
    assert!(e.to_string().contains("tool.mas"), "{e}");
    let e = Scene::from_toml_str("[gripper]\nmass = 0.1\n").unwrap_err();
    assert!(e.to_string().contains("gripper"), "{e}");
}

#[test]
fn rejects_wrong_type() {
    let mut s = Scene::default();
    let e = s.set_from_str("tool.mass", "heavy").unwrap_err();
    assert!(matches!(e, ConfigError::WrongType { .. }));
    let m = e.to_string();
    assert!(
        m.contains("tool.mass") && m.contains("heavy") && m.contains("number"),
        "{m}"
    );
    let e = Scene::from_toml_str("[object]\nenabled = 1\n").unwrap_err();
    assert!(
        e.to_string().contains("object.enabled") && e.to_string().contains("true or false"),
        "{e}"
    );
}

#[test]
fn rejects_unknown_module_name() {
    let mut s = Scene::default();
    let m = s
        .set_from_str("module", "pneumatic")
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("module") && m.contains("pneumatic") && m.contains("hydraulic"),
        "{m}"
    );
}

#[test]
fn rejects_unreadable_file() {
    let e = Scene::from_file(std::path::Path::new("/nonexistent/scene.toml")).unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains("/nonexistent/scene.toml") && m.contains("cannot read"),
        "{m}"
    );
}

#[test]
fn toml_syntax_error_names_the_line() {
    let e = Scene::from_toml_str("module = \"rigid\"\n[robot]\ndead_time = = 0.01\n").unwrap_err();
    let m = e.to_string();
    assert!(m.contains("line 3"), "{m}");
}

#[test]
fn rejects_bad_bistable_offset_and_gas_exponent() {
    invalid_in(&[("module", "bistable")], "bistable.offset", "0.02");
    invalid_after("hydraulic.gas_exponent", "1.0");
}

#[test]
fn rejects_cavitation_pressure_above_gas_pressure() {
    let m = invalid_in(
        &[("hydraulic.cavitation", "true")],
        "hydraulic.cavitation_pressure",
        "2000",
    );
    assert!(m.contains("hydraulic.gas_pressure"), "{m}");
}

#[test]
fn rejects_main_chamber_smaller_than_the_stroke_volume() {
    // a compressible liquid: the chamber volume is used
    let mut s = Scene::default();
    s.set_from_str("hydraulic.bulk_modulus", "1.5e9").unwrap();
    s.set_from_str("hydraulic.chamber_volume", "1e-5").unwrap();
    let err = s.validate().unwrap_err();
    assert_eq!(err.key(), Some("hydraulic.chamber_volume"), "{err}");
    assert!(err.to_string().contains("stroke"), "{err}");
    invalid_after("hydraulic.bulk_modulus", "-1");
    invalid_after("hydraulic.chamber_volume", "-1");
}

/// A part's keys constrain only the scenes that have the part: a lumped hydraulic scene with a
/// 27 mm piston is valid whatever the compressible model's chamber would need (its default
/// follows the geometry: the swept volume plus a dead volume), a rigid scene carries a
/// hydraulic section it does not use, a hydraulic one a bistable section, a scene without an
/// object an object section; each is refused once the part is in the scene.
#[test]
fn a_part_constrains_only_the_scenes_that_have_it() {
    let scene = |sets: &[(&str, &str)]| {
        let mut s = Scene::default();
        for (k, v) in sets {
            s.set_from_str(k, v).unwrap();
        }
        s
    };
    let big_piston = scene(&[("hydraulic.piston_radius", "0.027")]);
    big_piston.validate().unwrap();
    let a_p_l = big_piston.piston_area() * big_piston.stops.stroke;
    assert_eq!(
        big_piston.main_chamber_volume(),
        a_p_l + cushion_model::config::DEAD_VOLUME
    );
    scene(&[
        ("hydraulic.piston_radius", "0.027"),
        ("hydraulic.bulk_modulus", "1.5e9"),
    ])
    .validate()
    .unwrap();
    // the default chamber of the paper's geometry
    let paper = Scene::default().main_chamber_volume();
    assert!((paper - 4.0e-5).abs() < 1e-8, "{paper}");

    for (unused, part, key) in [
        (
            vec![("module", "rigid"), ("hydraulic.orifice_radius", "0.05")],
            vec![("module", "hydraulic")],
            "hydraulic.orifice_radius",
        ),
        (
            vec![("bistable.half_span", "-1")],
            vec![("module", "bistable")],
            "bistable.half_span",
        ),
        (
            vec![("object.enabled", "false"), ("object.mass", "0")],
            vec![("object.enabled", "true")],
            "object.mass",
        ),
        (
            vec![("module", "rigid"), ("tool.sensor_threshold", "1")],
            vec![("module", "bistable")],
            "tool.sensor_threshold",
        ),
        (
            vec![("hydraulic.cavitation_pressure", "5000")],
            vec![("hydraulic.cavitation", "true")],
            "hydraulic.cavitation_pressure",
        ),
    ] {
        let without = scene(&unused);
        without
            .validate()
            .unwrap_or_else(|e| panic!("{unused:?}: {e}"));
        let r = simulate(&without, &RunOptions::default());
        assert_eq!(
            r.summary.status,
            RunStatus::Ok,
            "{unused:?}: {}",
            r.summary.message
        );
        let mut with = without.clone();
        for (k, v) in &part {
            with.set_from_str(k, v).unwrap();
        }
        let err = with.validate().unwrap_err();
        assert_eq!(err.key(), Some(key), "{unused:?} + {part:?}: {err}");
    }
    // a value that is no number is refused in any scene
    invalid_after("bistable.half_span", "nan");
}

/// Every key, for each module, set to values a user may mistype or push to an extreme: either
/// `--set` or validation refuses it with a message naming the key and the value, or the scene
/// runs to a status (an accepted extreme may end `max_steps` or `stiff`, never in a panic).
#[test]
fn every_key_at_extreme_values_is_refused_by_name_or_runs() {
    let values = [
        "0",
        "-1",
        "-0.0",
        "1e-300",
        "1e-30",
        "0.5",
        "2",
        "1e30",
        "1e308",
        "-1e308",
        "nan",
        "inf",
        "abc",
        "true",
        "18446744073709551617",
    ];
    let (mut refused, mut ran) = (0, 0);
    for module in ["hydraulic", "bistable", "rigid"] {
        for &key in Scene::keys() {
            if key == "module" {
                continue;
            }
            for value in values {
                let mut s = Scene::default();
                s.set_from_str("module", module).unwrap();
                // a run that an extreme value keeps stepping is cut short: the point here is
                // that it ends with a status
                s.set_from_str("solver.max_steps", "20000").unwrap();
                let err = match s.set_from_str(key, value) {
                    Err(e) => Some(e),
                    Ok(()) => s.validate().err(),
                };
                match err {
                    Some(e) => {
                        refused += 1;
                        let m = e.to_string();
                        let named = e.key().is_some_and(|k| m.contains(k));
                        assert!(named, "{module} {key}={value}: {m}");
                        if e.key() == Some(key) {
                            // the value as typed, or as the key read it (`-0.0` is `-0` as
                            // a number and `0` as a count)
                            let read: Vec<String> = value
                                .parse::<f64>()
                                .map(|v| vec![v.to_string(), (v as i64).to_string()])
                                .unwrap_or_default();
                            assert!(
                                m.contains(value) || read.iter().any(|r| m.contains(r.as_str())),
                                "{module} {key}={value}: {m}"
                            );
                        }
                    }
                    None => {
                        ran += 1;
                        let r = simulate(&s, &RunOptions::default());
                        assert_ne!(
                            r.summary.status,
                            RunStatus::Invalid,
                            "{module} {key}={value}"
                        );
                    }
                }
            }
        }
    }
    // both paths were taken many times
    assert!(refused > 500 && ran > 500, "refused {refused}, ran {ran}");
}
