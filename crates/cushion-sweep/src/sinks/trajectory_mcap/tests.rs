//! Tests of `trajectory_mcap.rs`.

use super::*;
use crate::mcap_read::{read_run, recorded_runs, ReadError};

fn point(t: f64, with_object: bool) -> TrajectoryPoint {
    TrajectoryPoint {
        t,
        x_r: t,
        v_r: 1.0,
        x_t: t - 1e-4,
        v_t: 0.9,
        x_p: if with_object {
            1e-3 + 0.5 * t
        } else {
            f64::NAN
        },
        v_p: if with_object { 0.5 } else { f64::NAN },
        s: 1e-4,
        p1: 1000.0 + t * 10.0,
        f_c: 3.25,
        f_r: -1.0 / 3.0,
    }
}

fn sample() -> (Trajectory, Vec<EventLogEntry>) {
    let traj = Trajectory {
        points: (0..50).map(|i| point(i as f64 * 0.006, true)).collect(),
    };
    let events = vec![
        EventLogEntry {
            t: 0.0123,
            name: "sensor".into(),
            point: point(0.0123, true),
        },
        EventLogEntry {
            t: 0.0823,
            name: "brake".into(),
            point: point(0.0823, true),
        },
    ];
    (traj, events)
}

use cushion_model::{simulate, Module, RunOptions, RunStatus, Scene};

/// One simulated run: its trajectory (every step's end and every event) and event log.
fn recorded(scene: &Scene) -> (Trajectory, Vec<EventLogEntry>) {
    let r = simulate(
        scene,
        &RunOptions {
            trajectory: true,
            sample_interval: None,
        },
    );
    assert_eq!(r.summary.status, RunStatus::Ok, "{}", r.summary.message);
    (r.trajectory.expect("trajectory recorded"), r.events)
}

fn rigid_without_object() -> Scene {
    let mut scene = Scene {
        module: Module::Rigid,
        ..Scene::default()
    };
    scene.object.enabled = false;
    scene
}

/// An MCAP file holding the given runs, each under its topic prefix.
fn file_of(runs: &[(&str, &Trajectory, &[EventLogEntry])]) -> Vec<u8> {
    let mut buf = std::io::Cursor::new(Vec::new());
    {
        let mut w = write_options().create(&mut buf).unwrap();
        for (prefix, traj, events) in runs {
            write_run(&mut w, prefix, traj, events).unwrap();
        }
        w.finish().unwrap();
    }
    buf.into_inner()
}

fn same_bits(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || a.to_bits() == b.to_bits()
}

fn assert_same_point(written: &TrajectoryPoint, read: &TrajectoryPoint, what: &str) {
    for (i, (w, r)) in written.values().iter().zip(read.values()).enumerate() {
        assert!(
            same_bits(*w, r),
            "{what}, {}: wrote {w:e} ({:#018x}), read {r:e} ({:#018x})",
            TrajectoryPoint::COLUMNS[i],
            w.to_bits(),
            r.to_bits()
        );
    }
}

fn assert_bit_identical(
    written: (&Trajectory, &[EventLogEntry]),
    read: (&Trajectory, &[EventLogEntry]),
) {
    assert_eq!(written.0.points.len(), read.0.points.len(), "point count");
    for (k, (w, r)) in written.0.points.iter().zip(&read.0.points).enumerate() {
        assert_same_point(w, r, &format!("point {k}"));
    }
    assert_eq!(written.1.len(), read.1.len(), "event count");
    for (k, (w, r)) in written.1.iter().zip(read.1).enumerate() {
        assert_eq!(w.name, r.name, "event {k}");
        assert!(same_bits(w.t, r.t), "event {k} ({}): t", w.name);
        assert_same_point(&w.point, &r.point, &format!("event {k} ({})", w.name));
    }
}

#[test]
fn default_scene_reads_back_bit_for_bit() {
    let (traj, events) = recorded(&Scene::default());
    assert!(traj.points.len() > 100 && !events.is_empty());
    let bytes = file_of(&[("", &traj, &events)]);
    let (t2, e2) = read_run(&bytes, None).unwrap();
    assert_bit_identical((&traj, &events), (&t2, &e2));
    assert!(t2
        .points
        .iter()
        .all(|p| p.values().iter().all(|v| v.is_finite())));
    assert_eq!(recorded_runs(&bytes).unwrap(), Vec::<u64>::new());
    assert_eq!(
        read_run(&bytes, Some(0)),
        Err(ReadError::NoSuchRun {
            run: Some(0),
            available: vec![]
        })
    );
}

#[test]
fn rigid_scene_without_object_reads_back_with_absent_quantities_nan() {
    let (traj, events) = recorded(&rigid_without_object());
    let bytes = file_of(&[("", &traj, &events)]);
    let (t2, e2) = read_run(&bytes, None).unwrap();
    assert_bit_identical((&traj, &events), (&t2, &e2));
    assert!(!t2.points.is_empty());
    for p in t2.points.iter().chain(e2.iter().map(|e| &e.point)) {
        assert!(p.x_p.is_nan() && p.v_p.is_nan() && p.p1.is_nan(), "{p:?}");
        assert!(p.t.is_finite() && p.x_r.is_finite() && p.f_r.is_finite());
    }
}

#[test]
fn sweep_file_runs_are_listed_and_read_by_number() {
    let (ta, ea) = recorded(&Scene::default());
    let (tb, eb) = recorded(&rigid_without_object());
    let bytes = file_of(&[("/run/3", &ta, &ea), ("/run/7/", &tb, &eb)]);
    assert_eq!(recorded_runs(&bytes).unwrap(), vec![3, 7]);
    let (t3, e3) = read_run(&bytes, Some(3)).unwrap();
    assert_bit_identical((&ta, &ea), (&t3, &e3));
    let (t7, e7) = read_run(&bytes, Some(7)).unwrap();
    assert_bit_identical((&tb, &eb), (&t7, &e7));

    let missing = read_run(&bytes, Some(5)).unwrap_err();
    assert_eq!(
        missing,
        ReadError::NoSuchRun {
            run: Some(5),
            available: vec![3, 7]
        }
    );
    let text = missing.to_string();
    assert!(
        text.contains("run 5") && text.contains("runs 3, 7"),
        "{text}"
    );
    // two runs and no single-run topics: which one is meant is the caller's to say
    let ambiguous = read_run(&bytes, None).unwrap_err();
    assert!(
        matches!(ambiguous, ReadError::NoSuchRun { run: None, ref available } if *available == [3, 7])
    );
    assert!(ambiguous.to_string().contains("runs 3, 7"), "{ambiguous}");
}

#[test]
fn the_only_sweep_run_is_read_without_its_number() {
    let (traj, events) = sample();
    let bytes = file_of(&[("/run/12", &traj, &events)]);
    assert_eq!(recorded_runs(&bytes).unwrap(), vec![12]);
    let (t2, e2) = read_run(&bytes, None).unwrap();
    assert_bit_identical((&traj, &events), (&t2, &e2));
}

#[test]
fn a_run_without_events_reads_back_with_none() {
    let (traj, _) = sample();
    let bytes = file_of(&[
        ("/run/0", &traj, &[]),
        ("/run/17", &Trajectory::default(), &[]),
    ]);
    // channels without messages still name their run (the file's summary lists them)
    assert_eq!(recorded_runs(&bytes).unwrap(), vec![0, 17]);
    let (t0, e0) = read_run(&bytes, Some(0)).unwrap();
    assert_bit_identical((&traj, &[]), (&t0, &e0));
    let (t17, e17) = read_run(&bytes, Some(17)).unwrap();
    assert!(t17.points.is_empty() && e17.is_empty());
}

#[test]
fn garbage_is_not_mcap() {
    for bytes in [
        &b"definitely not an MCAP file, just some text"[..],
        &[][..],
        &[0x89, b'M', b'C', b'A', b'P', b'0', b'\r', b'\n'][..],
    ] {
        assert!(
            matches!(read_run(bytes, None), Err(ReadError::NotMcap(_))),
            "{:?}",
            read_run(bytes, None)
        );
        assert!(matches!(recorded_runs(bytes), Err(ReadError::NotMcap(_))));
    }
    // a real file cut short
    let (traj, events) = sample();
    let bytes = file_of(&[("", &traj, &events)]);
    let cut = &bytes[..bytes.len() / 2];
    assert!(matches!(read_run(cut, None), Err(ReadError::NotMcap(_))));
}

/// A file whose `/state` channel carries the given JSON messages.
fn file_with_state_messages(messages: &[&str]) -> Vec<u8> {
    let mut buf = std::io::Cursor::new(Vec::new());
    {
        let mut w = write_options().create(&mut buf).unwrap();
        let schema = w
            .add_schema(STATE_SCHEMA_NAME, "jsonschema", state_schema().as_bytes())
            .unwrap();
        let ch = w
            .add_channel(schema, "/state", "json", &BTreeMap::new())
            .unwrap();
        for (i, m) in messages.iter().enumerate() {
            let header = MessageHeader {
                channel_id: ch,
                sequence: i as u32,
                log_time: i as u64,
                publish_time: i as u64,
            };
            w.write_to_known_channel(&header, m.as_bytes()).unwrap();
        }
        w.finish().unwrap();
    }
    buf.into_inner()
}

#[test]
fn bad_messages_name_their_topic() {
    for (msg, says) in [
        (r#"{"t":"soon"}"#, "`t` is a string"),
        (r#"{"t":0.1,"#, "invalid JSON"),
        ("[1, 2]", "expected a JSON object"),
        (r#"{"t":1e999}"#, "out of range"),
    ] {
        let bytes = file_with_state_messages(&[r#"{"t":0}"#, msg]);
        match read_run(&bytes, None) {
            Err(ReadError::BadMessage { topic, message }) => {
                assert_eq!(topic, "/state");
                assert!(message.contains(says), "{msg}: {message}");
            }
            other => panic!("{msg}: {other:?}"),
        }
    }
    // other writers' spacing, nulls and extra fields are fine
    let bytes = file_with_state_messages(&[r#" { "t" : 0.5 , "x_r":null, "note":[true,{}] } "#]);
    let (t, _) = read_run(&bytes, None).unwrap();
    assert_eq!(t.points[0].t, 0.5);
    assert!(t.points[0].x_r.is_nan() && t.points[0].f_r.is_nan());
}

#[test]
fn json_numbers_round_trip_exactly() {
    let mut special = vec![
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        f64::MIN_POSITIVE / 3.0, // subnormal
        5e-324,
        f64::MAX,
        -f64::MAX,
        f64::EPSILON,
        0.1 + 0.2,
        394301.33835633675, // serde_json's default parser reads this one ulp low
        1e15,
        1e-4,
        9.999999999999999e14,
        -1.0 / 3.0,
    ];
    // xorshift64: random bit patterns (every exponent) and random values of the sizes a
    // trajectory holds
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    for _ in 0..100_000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        special.push(f64::from_bits(x));
        let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
        special.push(unit * 10f64.powi((x & 31) as i32 - 16));
    }
    for v in special.into_iter().filter(|v| v.is_finite()) {
        let mut text = String::new();
        push_number(&mut text, v);
        match serde_json::from_str::<serde_json::Value>(&text) {
            Ok(serde_json::Value::Number(n)) => {
                let r = n.as_f64().unwrap();
                assert_eq!(r.to_bits(), v.to_bits(), "{text}: read {r:e}")
            }
            other => panic!("{text}: {other:?}"),
        }
    }
}

#[test]
fn schemas_are_valid_json() {
    let s: serde_json::Value = serde_json::from_str(&state_schema()).unwrap();
    assert_eq!(s["properties"].as_object().unwrap().len(), 11);
    assert_eq!(s["properties"]["F_r"]["type"], "number");
    let e: serde_json::Value = serde_json::from_str(&event_schema()).unwrap();
    assert_eq!(
        e["properties"]["point"]["properties"]["p1"]["type"],
        "number"
    );
}

#[test]
fn absent_quantities_are_left_out() {
    let j: serde_json::Value = serde_json::from_str(&point_json(&point(0.1, false))).unwrap();
    let o = j.as_object().unwrap();
    assert_eq!(o.len(), 9);
    assert!(!o.contains_key("x_p") && !o.contains_key("v_p"));
    assert_eq!(o["F_r"].as_f64().unwrap(), -1.0 / 3.0);
}

#[test]
fn file_reads_back() {
    let (traj, events) = sample();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    write_mcap(&path, &traj, &events).unwrap();
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temp file left"
    );
    let bytes = std::fs::read(&path).unwrap();
    let msgs: Vec<_> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .collect();
    let state: Vec<_> = msgs
        .iter()
        .filter(|m| m.channel.topic == "/state")
        .collect();
    let ev: Vec<_> = msgs
        .iter()
        .filter(|m| m.channel.topic == "/events")
        .collect();
    assert_eq!(state.len(), 50);
    assert_eq!(ev.len(), 2);
    let schema = state[0].channel.schema.as_ref().unwrap();
    assert_eq!(schema.encoding, "jsonschema");
    assert_eq!(schema.name, STATE_SCHEMA_NAME);
    assert_eq!(state[0].channel.message_encoding, "json");
    assert_eq!(state[10].log_time, 60_000_000);
    assert_eq!(state[10].publish_time, 60_000_000);
    let v: serde_json::Value = serde_json::from_slice(&state[10].data).unwrap();
    assert_eq!(v["t"].as_f64().unwrap(), traj.points[10].t);
    assert_eq!(v["F_r"].as_f64().unwrap(), -1.0 / 3.0);
    assert_eq!(v["x_p"].as_f64().unwrap(), traj.points[10].x_p);
    let e: serde_json::Value = serde_json::from_slice(&ev[1].data).unwrap();
    assert_eq!(e["name"], "brake");
    assert_eq!(e["point"]["t"].as_f64().unwrap(), 0.0823);
    assert_eq!(ev[1].log_time, 82_300_000);

    // Indexed, with statistics (Foxglove seeks with these).
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("summary section");
    let stats = summary.stats.expect("statistics");
    assert_eq!(stats.message_count, 52);
    assert_eq!(stats.channel_count, 2);
    assert_eq!(stats.schema_count, 2);
    assert_eq!(stats.message_start_time, 0);
    assert_eq!(stats.message_end_time, time_ns(49.0 * 0.006));
    assert!(!summary.chunk_indexes.is_empty());
}

#[test]
fn several_runs_share_one_writer() {
    let (traj, events) = sample();
    let mut buf = std::io::Cursor::new(Vec::new());
    {
        let mut w = write_options().create(&mut buf).unwrap();
        write_run(&mut w, "/run/0", &traj, &events).unwrap();
        write_run(&mut w, "/run/17/", &traj, &[]).unwrap();
        w.finish().unwrap();
    }
    let bytes = buf.into_inner();
    let mut counts = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        *counts.entry(m.unwrap().channel.topic.clone()).or_insert(0) += 1;
    }
    assert_eq!(counts["/run/0/state"], 50);
    assert_eq!(counts["/run/0/events"], 2);
    assert_eq!(counts["/run/17/state"], 50);
    assert!(!counts.contains_key("/run/17/events"));
}
