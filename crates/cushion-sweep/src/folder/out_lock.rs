//! One sweep (or merge) at a time per output folder.
//!
//! Two sweeps writing into the same folder would interleave their chunks and overwrite each
//! other's summaries. `cushion sweep` and `cushion merge` therefore hold an advisory lock
//! (`flock`) on `<out>/.sweep.lock` from before they read or remove anything there until they
//! return. The operating system releases the lock when the process ends, however it ends, so a
//! killed sweep leaves no stale lock behind and `--resume` can always continue it. The empty
//! lock file itself stays: removing it would let a process that opened it just before the
//! removal and one that creates a new one both hold "the" lock.
//!
//! The lock is a safety net, not a requirement: on a file system that cannot lock (some network
//! and FUSE mounts answer `flock` with "not supported" or "no locks available") the command
//! goes on unprotected, with a warning.

use std::fs::{self, File, OpenOptions, TryLockError};
use std::io;
use std::path::Path;

use crate::error::{io_err, SweepError};

/// Name of the lock file inside the output folder.
pub const LOCK_FILE: &str = ".sweep.lock";

/// The lock on an output folder, released when dropped (or when the process ends).
#[derive(Debug)]
pub struct OutputLock {
    _file: File,
    /// Why the folder could not be locked, when it could not (the command goes on).
    not_locked: Option<io::Error>,
}

/// Why the lock was not taken.
#[derive(Debug)]
pub enum LockError {
    /// Another process holds it: a sweep is writing into the folder now.
    Held,
    /// The folder or the lock file could not be created.
    Io(io::Error),
}

impl OutputLock {
    /// Create `out_dir` if needed and take its lock without waiting.
    pub fn take(out_dir: &Path) -> Result<OutputLock, LockError> {
        fs::create_dir_all(out_dir).map_err(LockError::Io)?;
        let file = OpenOptions::new()
            .create(true)
            .write(true)
            .truncate(false)
            .open(out_dir.join(LOCK_FILE))
            .map_err(LockError::Io)?;
        let locked = file.try_lock();
        Self::from_attempt(file, locked)
    }

    /// The outcome of an attempt to lock `file`.
    fn from_attempt(file: File, locked: Result<(), TryLockError>) -> Result<OutputLock, LockError> {
        match locked {
            Ok(()) => Ok(OutputLock {
                _file: file,
                not_locked: None,
            }),
            Err(TryLockError::WouldBlock) => Err(LockError::Held),
            Err(TryLockError::Error(e)) => Ok(OutputLock {
                _file: file,
                not_locked: Some(e),
            }),
        }
    }

    /// The warning for the caller to pass on when the folder could not be locked.
    pub fn warning(&self, out_dir: &Path) -> Option<String> {
        self.not_locked.as_ref().map(|e| {
            format!(
                "{}: cannot lock {LOCK_FILE} ({e}); nothing keeps a second sweep out of this folder",
                out_dir.display()
            )
        })
    }
}

impl LockError {
    /// [`SweepError::Busy`] naming the folder when another process holds the lock,
    /// [`SweepError::Io`] otherwise.
    pub fn into_sweep_error(self, out_dir: &Path) -> SweepError {
        match self {
            LockError::Held => SweepError::Busy(format!(
                "{}: another cushion sweep or merge is writing into this folder now (it holds {LOCK_FILE}): wait for it to end, or choose another output folder",
                out_dir.display()
            )),
            LockError::Io(e) => io_err(out_dir.display(), e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_until_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a").join("b");
        let first = OutputLock::take(&out).unwrap();
        assert!(out.join(LOCK_FILE).exists());
        assert!(matches!(OutputLock::take(&out), Err(LockError::Held)));
        drop(first);
        let again = OutputLock::take(&out).unwrap();
        // another folder is independent
        let other = OutputLock::take(&dir.path().join("c")).unwrap();
        drop((again, other));
    }

    #[test]
    fn a_file_system_that_cannot_lock_gives_a_warning_not_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        let file = File::create(out.join(LOCK_FILE)).unwrap();
        let unsupported = io::Error::from(io::ErrorKind::Unsupported);
        let lock = OutputLock::from_attempt(file, Err(TryLockError::Error(unsupported))).unwrap();
        let w = lock.warning(out).unwrap();
        assert!(w.contains("cannot lock"), "{w}");
        // a lock taken for real warns of nothing
        drop(lock);
        assert_eq!(OutputLock::take(out).unwrap().warning(out), None);
    }

    #[test]
    fn a_folder_that_cannot_be_made_is_an_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("f");
        fs::write(&file, b"x").unwrap();
        assert!(matches!(
            OutputLock::take(&file.join("o")),
            Err(LockError::Io(_))
        ));
    }
}
