//! Why a design question cannot be asked or answered. Bad input is one kind (the command maps it
//! to exit status 2, the bindings to `ConfigError`); a caller that breaks the ask/tell protocol
//! is another, so a binding can tell the user's mistake from its own.

/// What went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// Bad input: the key, the value given and what is allowed.
    #[error("{key} = {value}: {allowed}")]
    Config {
        key: String,
        value: String,
        allowed: String,
    },
    /// The caller broke the ask/tell protocol (results of the wrong length, results for no
    /// batch, a question about a map not yet refined).
    #[error("{0}")]
    Protocol(String),
}

/// A [`DesignError::Config`] from its three parts.
pub(crate) fn config(
    key: impl Into<String>,
    value: impl std::fmt::Display,
    allowed: impl Into<String>,
) -> DesignError {
    DesignError::Config {
        key: key.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}
