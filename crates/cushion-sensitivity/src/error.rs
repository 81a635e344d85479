//! Why a sample, a distribution or an analysis cannot be made. Every message names the key (or
//! the output), the value given and what is allowed, so a command or a binding can show it as is.

/// What went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensitivityError {
    /// Bad input: the key, the value given and what is allowed.
    #[error("{key} = {value}: {allowed}")]
    Config {
        key: String,
        value: String,
        allowed: String,
    },
    /// An output column that the estimators cannot use (its length does not fit the layout, or
    /// a value is not finite). `output` is the column's position in the slice given.
    #[error("output {output}: {problem}")]
    Output { output: usize, problem: String },
    /// Runs of the sample did not end `ok`, and the study was told to stop on them.
    #[error("{0}")]
    FailedRuns(String),
    /// A file could not be written or read.
    #[error("{0}")]
    Io(String),
}

/// A [`SensitivityError::Config`] from its three parts.
pub(crate) fn config(
    key: impl Into<String>,
    value: impl std::fmt::Display,
    allowed: impl Into<String>,
) -> SensitivityError {
    SensitivityError::Config {
        key: key.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}
