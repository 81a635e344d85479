//! The command line as a whole: `--version` (with the commit it was built from), shell
//! completions, and clap's usage errors, with their exit statuses.

use std::process::{Command, Output};

fn cushion(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cushion"))
        .args(args)
        .output()
        .expect("run cushion")
}

fn text(b: &[u8]) -> String {
    String::from_utf8(b.to_vec()).unwrap()
}

/// The commit of this checkout, if the tests run in one.
fn head_commit() -> Option<String> {
    let o = Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    o.status
        .success()
        .then(|| text(&o.stdout).trim().to_string())
}

#[test]
fn version_names_the_package_and_the_commit() {
    let o = cushion(&["--version"]);
    assert_eq!(o.status.code(), Some(0));
    let line = text(&o.stdout);
    let expect = format!("cushion {}", env!("CARGO_PKG_VERSION"));
    assert!(line.starts_with(&expect), "{line}");
    match head_commit() {
        // built from this checkout at this commit (cargo rebuilds the line when HEAD moves)
        Some(c) => assert_eq!(line.trim(), format!("{expect} (commit {c})")),
        None => assert_eq!(line.trim(), expect),
    }
}

#[test]
fn completions_for_bash_zsh_and_fish() {
    for (shell, marker) in [
        ("bash", "complete -F _cushion"),
        ("zsh", "#compdef cushion"),
        ("fish", "complete -c cushion"),
    ] {
        let o = cushion(&["completions", shell]);
        assert_eq!(o.status.code(), Some(0), "{shell}");
        let script = text(&o.stdout);
        assert!(script.contains(marker), "{shell}: {script}");
        for word in ["simulate", "sweep", "merge", "sample-interval", "resume"] {
            assert!(script.contains(word), "{shell} lacks {word}");
        }
    }
    let o = cushion(&["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("tcsh"));
}

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    let o = cushion(&["simulat"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("simulat"));
    let o = cushion(&[]);
    assert_eq!(o.status.code(), Some(2));
    let o = cushion(&["--help"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(text(&o.stdout).contains("completions"));
}
