//! `cushion-sensitivity`: global sensitivity of a model's outputs to its uncertain inputs, the
//! engine-free core. *Which inputs drive an output, alone and through which interactions?*
//!
//! Three pieces, none of which knows the model or runs anything:
//! - [`SaltelliSample`]: the rows of a Saltelli sample as unit points, each a pure function of
//!   its row number, in SALib's layout;
//! - [`Marginal`]: an input's [`Distribution`] (uniform, loguniform, normal, lognormal,
//!   triangular), optionally truncated, drawn by the inverse CDF of a unit coordinate;
//! - [`analyze`]: SALib's Sobol estimators over many output columns at once, with seeded
//!   bootstrap intervals, parallel and independent of the thread count.
//!
//! Above them, still engine-free, the study layer of `cushion sensitivity` ([`study`], [`chart`]):
//! a run summary's Arrow columns in, the failed runs dealt with, the long table (Parquet, CSV)
//! and its SVG chart out.
//!
//! # The sample
//!
//! `D` inputs, `N` base points. Base point `i` is point `i` of an Owen-scrambled Sobol sequence
//! in `2D` dimensions; its first `D` coordinates form the row `A_i`, the last `D` the row `B_i`.
//! `AB_i^j` is `A_i` with coordinate `j` taken from `B_i`, and `BA_i^j` is `B_i` with coordinate
//! `j` taken from `A_i`. The sample is, for each base point in turn, the block of rows
//!
//! ```text
//! A_i, AB_i^1 .. AB_i^D, [BA_i^1 .. BA_i^D,] B_i
//! ```
//!
//! `N (2D + 2)` rows with second order, `N (D + 2)` without: the layout of SALib's
//! `SALib.sample.sobol.sample` (Saltelli's scheme), so SALib's `analyze` reads the outputs of
//! this sample as its own. Only the base points differ from SALib's (they are `sobol_burley`'s,
//! seeded; SALib's are SciPy's).
//!
//! # The estimators
//!
//! As `SALib.analyze.sobol.analyze` (SALib 1.6) computes them, to rounding. The output column
//! `Y` is first normalised over all its rows, `Y ← (Y - mean Y) / std Y` (`std` with `ddof =
//! 0`); this matters for `S1` and `S2`, which unlike `ST` are not invariant to a shift of `Y`.
//! Writing `a_i, b_i, ab_i^j, ba_i^j` for the normalised outputs of the rows above and `V` for
//! the variance (`ddof = 0`) of the `2N` values `a_1..a_N, b_1..b_N`:
//!
//! ```text
//! S1_j  = (1/N) Σ_i b_i (ab_i^j - a_i) / V                        Saltelli et al. (2010)
//! ST_j  = (1/2N) Σ_i (a_i - ab_i^j)² / V                          Jansen (1999)
//! S2_jk = (1/N) Σ_i (ba_i^j ab_i^k - a_i b_i) / V - S1_j - S1_k   Saltelli (2002)
//! ```
//!
//! As in SALib, an index is 0 where `V <= ε` (machine epsilon), and every index and interval is
//! 0 when the normalised `a` and `b` values span no more than `ε` (the output varies only on
//! `AB`/`BA` rows). An output that is constant over the whole sample, which SALib would turn into
//! NaN (`std Y = 0`), is reported as [`Sensitivity::Constant`].
//!
//! **Intervals** (SALib's bootstrap): `R` resamples, each drawing `N` base points with
//! replacement and computing every index from their rows alone (its own `V` included); the
//! interval's half-width is `conf = Φ⁻¹(1/2 + level/2) · sd(R estimates)` (`ddof = 1`). Resample
//! `b` draws from its own ChaCha8 stream of the seed, and every output is resampled with the same
//! base points, so the intervals depend on the outputs and the seed only, never on the threads.
//! The draws are not NumPy's, so the intervals agree with SALib's in distribution, not to the
//! digit; the point estimates agree to rounding.
//!
//! # References
//!
//! - I. M. Sobol' (2001), "Global sensitivity indices for nonlinear mathematical models and their
//!   Monte Carlo estimates", Mathematics and Computers in Simulation 55, 271-280.
//! - A. Saltelli (2002), "Making best use of model evaluations to compute sensitivity indices",
//!   Computer Physics Communications 145, 280-297 (the sample scheme; `S2`).
//! - A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola (2010), "Variance
//!   based sensitivity analysis of model output. Design and estimator for the total sensitivity
//!   index", Computer Physics Communications 181, 259-270 (`S1`, table 2 (b)).
//! - M. J. W. Jansen (1999), "Analysis of variance designs for model output", Computer Physics
//!   Communications 117, 35-43 (`ST`; table 2 (f) of Saltelli et al. 2010).
//! - J. Herman, W. Usher (2017), "SALib: An open-source Python library for sensitivity
//!   analysis", Journal of Open Source Software 2(9); `SALib.sample.sobol` and
//!   `SALib.analyze.sobol` (version 1.6) are the layout and the estimators matched here.
//! - M. J. Wichura (1988), "Algorithm AS 241: The percentage points of the normal
//!   distribution", Applied Statistics 37, 477-484 (`Φ⁻¹`, see [`normal`]).

pub mod chart;
pub mod distribution;
pub mod error;
mod long_table;
pub mod normal;
pub mod saltelli;
pub mod sobol;
pub mod study;
mod study_options;

pub use distribution::{Distribution, Domain, Marginal};
pub use error::SensitivityError;
pub use saltelli::{block_len, RowKind, SaltelliSample};
pub use sobol::{analyze, Estimate, PairEstimate, Sensitivity, SobolIndices, SobolOptions};
pub use study::{run_study, Finding, OnFailed, Study, StudyOptions};
