//! Why an attempted step produced no step: what a method reports and a controller answers.

/// Why an attempt produced no step. The loop retries it smaller (an adaptive method) and
/// counts it as rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepFailure {
    /// A stage, the new state or the error estimate is not finite (a trial stage left the
    /// domain of `f`). Found by the loop from the attempt's numbers.
    NonFinite,
    /// The iteration matrix (`I / (h gamma) - J` for a Rosenbrock method) is singular.
    SingularMatrix,
}

impl std::fmt::Display for StepFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StepFailure::NonFinite => "a non-finite stage",
            StepFailure::SingularMatrix => "a singular iteration matrix",
        })
    }
}
