//! Why a sweep or a merge could not finish. Each kind maps onto one answer for the caller: the
//! command's exit status ([`SweepError::exit_code`]) and the Python exception the bindings raise
//! (`ConfigError`, `OSError`, `BlockingIOError`, `KeyboardInterrupt`, `RuntimeError`), so no
//! caller has to read the message to decide.

/// A sweep or merge that could not finish.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// Bad input: the sweep file, an option, a scene of one of its runs, or a folder that holds
    /// something else. The message names the key or line, the value and what is allowed.
    #[error("{0}")]
    Config(String),
    /// Another sweep or merge is writing into the output folder now.
    #[error("{0}")]
    Busy(String),
    /// Reading or writing a file failed (disk full, permissions, a damaged file).
    #[error("{0}")]
    Io(String),
    /// The caller's cancel flag was raised; finished chunks are on disk and `resume` continues.
    #[error("the sweep was cancelled; finished chunks are kept and resume continues it")]
    Cancelled,
    /// A failure of this library rather than of the input or the disk.
    #[error("internal error: {0}")]
    Internal(String),
}

impl SweepError {
    /// The exit status the command uses: 2 for input the user must fix (bad input, a busy
    /// folder), 130 for a cancelled sweep (as a shell reports SIGINT), 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            SweepError::Config(_) | SweepError::Busy(_) => 2,
            SweepError::Cancelled => 130,
            SweepError::Io(_) | SweepError::Internal(_) => 1,
        }
    }
}

/// An I/O error about `what`: `"{what}: {e}"`.
pub(crate) fn io_err(what: impl std::fmt::Display, e: impl std::fmt::Display) -> SweepError {
    SweepError::Io(format!("{what}: {e}"))
}
