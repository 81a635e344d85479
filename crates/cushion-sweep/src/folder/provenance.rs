//! `provenance.json`: what a sweep output holds and how it was made, and the digest that tells
//! whether a folder holds the same sweep (for `resume` and `merge`).

use std::fs;
use std::path::Path;

use cushion_model::Scene;

use crate::sweep_file::SweepFile;

/// FNV-1a, 64 bits: a stable digest of what a sweep computes (file text and resolved scene).
pub fn digest(parts: &[&str]) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for p in parts {
        for b in p.as_bytes().iter().chain(std::iter::once(&0u8)) {
            h ^= *b as u64;
            h = h.wrapping_mul(0x100000001b3);
        }
    }
    format!("{h:016x}")
}

/// The digest of a sweep: its text and its base scene with `[set]` applied.
pub fn sweep_digest(sweep: &SweepFile) -> String {
    let base = toml::to_string(&sweep.base.to_toml()).unwrap_or_default();
    digest(&[&sweep.text, &base])
}

/// A finished sweep of the same digest and shard is in `out_dir`.
pub fn finished_same(out_dir: &Path, digest: &str, shard: (usize, usize)) -> bool {
    let Ok(bytes) = fs::read(out_dir.join("provenance.json")) else {
        return false;
    };
    let Ok(p) = serde_json::from_slice::<serde_json::Value>(&bytes) else {
        return false;
    };
    out_dir.join("summary.parquet").exists()
        && p["sweep_digest"] == digest
        && p["shard"]["k"] == shard.0
        && p["shard"]["n"] == shard.1
}

/// Seconds since the Unix epoch, for `finished_unix_time` (0 if the clock is before it).
pub fn unix_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

/// Every `solver.*` key of `scene` with its value, for the `solver` entry of a provenance.
pub fn solver_settings(scene: &Scene) -> serde_json::Map<String, serde_json::Value> {
    Scene::keys()
        .iter()
        .filter(|k| k.starts_with("solver."))
        .map(|k| {
            let value = scene
                .get(k)
                .ok()
                .and_then(|v| serde_json::to_value(v).ok())
                .unwrap_or(serde_json::Value::Null);
            (k.to_string(), value)
        })
        .collect()
}

/// The resolved scene as TOML-shaped JSON, for the `base_scene` entry of a provenance.
pub fn base_scene(scene: &Scene) -> serde_json::Value {
    serde_json::to_value(scene.to_toml()).unwrap_or(serde_json::Value::Null)
}

/// What one invocation of a sweep did, for its provenance.
pub struct Record<'a> {
    pub sweep: &'a SweepFile,
    pub digest: &'a str,
    pub git_commit: Option<&'a str>,
    pub n_runs: u64,
    pub shard: (usize, usize),
    pub runs_in_output: u64,
    pub failed: usize,
    pub runs_now: u64,
    pub resumed: bool,
    pub threads: usize,
    pub wall: f64,
    /// Wall time and count of the earlier invocations of a resumed sweep.
    pub earlier: (f64, usize),
}

impl Record<'_> {
    pub fn to_json(&self) -> serde_json::Value {
        let sweep = self.sweep;
        serde_json::json!({
            "cushion_version": env!("CARGO_PKG_VERSION"),
            "git_commit": self.git_commit,
            "sweep_file": sweep.path.display().to_string(),
            "sweep_name": sweep.name,
            "sweep_digest": self.digest,
            "mode": sweep.mode.name(),
            "samples": sweep.samples,
            "seed": sweep.seed,
            "axes": sweep.axes.iter().map(|a| a.key.clone()).collect::<Vec<_>>(),
            "n_runs_total": self.n_runs,
            "shard": { "k": self.shard.0, "n": self.shard.1 },
            "runs_in_output": self.runs_in_output,
            "runs_failed": self.failed,
            "runs_computed_now": self.runs_now,
            "resumed": self.resumed,
            "threads": self.threads,
            "chunk_size": sweep.chunk_size,
            "wall_seconds": self.wall,
            "wall_seconds_all_invocations": self.earlier.0 + self.wall,
            "invocations": self.earlier.1 + 1,
            "finished_unix_time": unix_now(),
            "solver": solver_settings(&sweep.base),
            "base_scene": base_scene(&sweep.base),
        })
    }
}
