//! The version line of `cushion --version`: the package version and, when the crate is built
//! from a git checkout, the commit (provenance files record it too; a binary or wheel that
//! outlives its checkout still says what it was built from).

use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (out.status.success() && !s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let version = env!("CARGO_PKG_VERSION");
    let line = match git(&["rev-parse", "HEAD"]) {
        Some(commit) => {
            // Build again when HEAD moves: HEAD itself (a checkout) and the branch it names (a
            // commit). A path that does not exist would make cargo rebuild every time.
            for what in ["HEAD", "refs/heads"] {
                if let Some(p) = git(&["rev-parse", "--path-format=absolute", "--git-path", what]) {
                    if Path::new(&p).exists() {
                        println!("cargo:rerun-if-changed={p}");
                    }
                }
            }
            if let Some(p) = git(&[
                "rev-parse",
                "--path-format=absolute",
                "--git-path",
                "packed-refs",
            ]) {
                if Path::new(&p).exists() {
                    println!("cargo:rerun-if-changed={p}");
                }
            }
            format!("{version} (commit {commit})")
        }
        None => version.to_string(),
    };
    println!("cargo:rustc-env=CUSHION_VERSION_LINE={line}");
}
