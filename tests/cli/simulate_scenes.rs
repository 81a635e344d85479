//! Every shipped scene file (`sweeps/scenes/*.toml`) runs through `cushion simulate` and ends
//! `ok`; its JSON equals the same scene given key by key with `--set`.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn simulate(args: &[&str]) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_cushion"))
        .arg("simulate")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// `section.name=value` for every leaf of a scene table.
fn flatten(prefix: &str, table: &toml::Table, out: &mut Vec<String>) {
    for (k, v) in table {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => flatten(&key, t, out),
            toml::Value::String(s) => out.push(format!("{key}={s}")),
            other => out.push(format!("{key}={other}")),
        }
    }
}

#[test]
fn shipped_scenes_run_and_match_set() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps/scenes");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return;
    };
    let mut n = 0;
    for e in entries {
        let path = e.unwrap().path();
        if path.extension().and_then(|x| x.to_str()) != Some("toml") {
            continue;
        }
        let from_file = simulate(&[path.to_str().unwrap()]);
        assert_eq!(from_file["status"], "ok", "{}", path.display());

        let table: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
        let mut sets = Vec::new();
        flatten("", &table, &mut sets);
        let mut args = Vec::new();
        for s in &sets {
            args.push("--set");
            args.push(s.as_str());
        }
        assert_eq!(
            simulate(&args),
            from_file,
            "{}: file vs --set",
            path.display()
        );
        n += 1;
    }
    eprintln!("{n} scene files");
}
