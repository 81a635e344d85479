//! Wall time across the invocations of one sweep: a sweep that is killed and resumed runs in
//! several processes, and its `provenance.json` should say what the whole sweep cost.
//!
//! Each invocation keeps `elapsed-<id>.json` in the sweep's state folder (`DIR/.sweep/`): its
//! seconds since it started, rewritten after every chunk it finishes (a temporary file and a
//! rename, no fsync: bookkeeping, not results). A killed invocation's file holds its time up to
//! its last finished chunk; the time it spent on the chunk in flight is not counted (that chunk
//! is computed again, and counted, by the next invocation). The invocation that finishes adds the
//! earlier ones to its own wall time (`wall_seconds_all_invocations`, `invocations`).

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;

const PREFIX: &str = "elapsed-";
const SUFFIX: &str = ".json";

/// This process's share of a sweep.
pub(crate) struct Invocation {
    state_dir: PathBuf,
    file_name: String,
    started: Instant,
}

impl Invocation {
    /// An invocation that started at `started`, keeping its record in `state_dir`. Its id is the
    /// start time (ns since the epoch) and the process id, so ids sort by start time.
    pub fn new(state_dir: &Path, started: Instant) -> Invocation {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        Invocation {
            state_dir: state_dir.to_path_buf(),
            file_name: format!("{PREFIX}{nanos:020}-{}{SUFFIX}", std::process::id()),
            started,
        }
    }

    /// Record the seconds since this invocation started (after each finished chunk).
    pub fn record(&self) -> io::Result<()> {
        let seconds = self.started.elapsed().as_secs_f64();
        let tmp = self.state_dir.join(format!("{}.tmp", self.file_name));
        fs::write(&tmp, serde_json::json!({ "seconds": seconds }).to_string())?;
        fs::rename(&tmp, self.state_dir.join(&self.file_name))
    }

    /// The seconds and the number of the earlier invocations recorded in the state folder (this
    /// one left out), in the order they started; unreadable records are skipped.
    pub fn earlier(&self) -> (f64, usize) {
        let Ok(entries) = fs::read_dir(&self.state_dir) else {
            return (0.0, 0);
        };
        let mut names: Vec<String> = entries
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(PREFIX) && n.ends_with(SUFFIX) && *n != self.file_name)
            .collect();
        names.sort();
        let seconds: Vec<f64> = names
            .iter()
            .filter_map(|n| fs::read(self.state_dir.join(n)).ok())
            .filter_map(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
            .filter_map(|v| v["seconds"].as_f64())
            .filter(|s| s.is_finite() && *s >= 0.0)
            .collect();
        (seconds.iter().sum(), seconds.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn earlier_invocations_are_summed_and_this_one_left_out() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        fs::write(
            d.join("elapsed-00000000000000000001-7.json"),
            r#"{"seconds": 1.5}"#,
        )
        .unwrap();
        fs::write(
            d.join("elapsed-00000000000000000002-8.json"),
            r#"{"seconds": 0.25}"#,
        )
        .unwrap();
        // not records: a torn temporary file, a broken record, a chunk
        fs::write(d.join("elapsed-00000000000000000003-9.json.tmp"), "{").unwrap();
        fs::write(d.join("elapsed-00000000000000000004-9.json"), "{").unwrap();
        fs::write(d.join("chunk-00000000.parquet"), "").unwrap();
        let me = Invocation::new(d, Instant::now());
        assert_eq!(me.earlier(), (1.75, 2));
        // its own record does not count for itself, and counts for the next invocation
        me.record().unwrap();
        assert_eq!(me.earlier(), (1.75, 2));
        let own: serde_json::Value =
            serde_json::from_slice(&fs::read(d.join(&me.file_name)).unwrap()).unwrap();
        let own = own["seconds"].as_f64().unwrap();
        assert!(own >= 0.0);
        let next = Invocation::new(d, Instant::now());
        assert_ne!(next.file_name, me.file_name);
        assert_eq!(next.earlier(), (1.75 + own, 3));
        assert!(!d.join(format!("{}.tmp", me.file_name)).exists());
    }
}
