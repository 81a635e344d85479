//! Uncertain inputs: a distribution, optionally truncated to a range, drawn by the inverse CDF of
//! a unit point, so that low-discrepancy points (Sobol, Latin hypercube, Saltelli) keep their
//! stratification through the mapping.
//!
//! Truncation to `[low, high]` maps `u` into `[F(low), F(high)]` before the inverse CDF:
//! `x = F⁻¹(F(low) + u (F(high) - F(low)))`. For a normal (and a lognormal, on the log scale)
//! whose range lies above the median, the mass is measured from the upper tail instead
//! (`Φ(-z)`), where double precision resolves it: a range 10 standard deviations out draws as
//! accurately as one around the mean.

use crate::error::{config, SensitivityError};
use crate::normal;

/// A distribution of one input, in the input's own units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Uniform on `[low, high]`.
    Uniform { low: f64, high: f64 },
    /// Uniform in the logarithm on `[low, high]`, `0 < low < high`.
    LogUniform { low: f64, high: f64 },
    /// Normal with mean `mean` and standard deviation `sd > 0`.
    Normal { mean: f64, sd: f64 },
    /// Lognormal: `ln x` normal with mean `ln median` and standard deviation `sigma > 0`.
    LogNormal { median: f64, sigma: f64 },
    /// Triangular on `[low, high]` with its peak at `mode`, `low <= mode <= high`.
    Triangular { low: f64, mode: f64, high: f64 },
}

impl Distribution {
    /// The name a sweep file gives it (`dist = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            Distribution::Uniform { .. } => "uniform",
            Distribution::LogUniform { .. } => "loguniform",
            Distribution::Normal { .. } => "normal",
            Distribution::LogNormal { .. } => "lognormal",
            Distribution::Triangular { .. } => "triangular",
        }
    }

    /// The interval outside which it has no mass (infinite ends for normal, 0 for lognormal).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Distribution::Uniform { low, high }
            | Distribution::LogUniform { low, high }
            | Distribution::Triangular { low, high, .. } => (low, high),
            Distribution::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Distribution::LogNormal { .. } => (0.0, f64::INFINITY),
        }
    }
}

/// What values the input may take, as the caller knows it (a mass, a radius or a pressure must
/// be positive; a position need not).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// Any real value.
    Real,
    /// Only values `> 0`: a distribution that can draw `<= 0` is refused.
    Positive,
}

/// For a normal or lognormal, `u` is held at `2⁻⁵³` from 0 and 1 (8.2 standard deviations out
/// when untruncated), the most that double precision resolves next to 1, so no draw is ever
/// infinite. Saltelli points never come that close (they lie in `[2⁻²⁴, 1 - 2⁻²⁴]`); with a
/// truncation the shift is `2⁻⁵³` of the range's mass.
const P_TAIL: f64 = 1.0 / (1u64 << 53) as f64;

/// A distribution with its truncation, checked and ready to draw from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marginal {
    dist: Distribution,
    range: Option<(f64, f64)>,
    /// The mass coordinate (see [`Marginal::mass`]) of the lower and the upper end of the
    /// draws; `u` maps linearly from one to the other.
    p_start: f64,
    p_end: f64,
    /// Normal and lognormal above the median: mass measured from the upper tail.
    upper_tail: bool,
}

/// The distribution's parameters and the range: finite, ordered, positive where they must be.
fn check_parameters(
    key: &str,
    dist: Distribution,
    range: Option<(f64, f64)>,
) -> Result<(), SensitivityError> {
    let finite = |name: &str, v: f64| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(config(
                format!("{key}: {name}"),
                v,
                "must be a finite number",
            ))
        }
    };
    let positive = |name: &str, v: f64| {
        if v > 0.0 {
            Ok(())
        } else {
            Err(config(format!("{key}: {name}"), v, "must be > 0"))
        }
    };
    let ordered = |what: &str, low: f64, high: f64| {
        if low < high {
            Ok(())
        } else {
            Err(config(
                format!("{key}: {what}"),
                format!("[{low}, {high}]"),
                "low must be below high",
            ))
        }
    };
    match dist {
        Distribution::Uniform { low, high } => {
            finite("low", low)?;
            finite("high", high)?;
            ordered("range", low, high)?;
        }
        Distribution::LogUniform { low, high } => {
            finite("low", low)?;
            finite("high", high)?;
            positive("low", low)?;
            ordered("range", low, high)?;
        }
        Distribution::Normal { mean, sd } => {
            finite("mean", mean)?;
            finite("sd", sd)?;
            positive("sd", sd)?;
        }
        Distribution::LogNormal { median, sigma } => {
            finite("median", median)?;
            finite("sigma", sigma)?;
            positive("median", median)?;
            positive("sigma", sigma)?;
        }
        Distribution::Triangular { low, mode, high } => {
            finite("low", low)?;
            finite("mode", mode)?;
            finite("high", high)?;
            ordered("range", low, high)?;
            if !(low..=high).contains(&mode) {
                return Err(config(
                    format!("{key}: mode"),
                    mode,
                    format!("must lie in the range [{low}, {high}]"),
                ));
            }
        }
    }
    if let Some((low, high)) = range {
        finite("range low", low)?;
        finite("range high", high)?;
        ordered("range", low, high)?;
    }
    Ok(())
}

/// A key that must be positive: the draws, which start at `d_low`, never reach 0 (a lognormal
/// approaches it without reaching it).
fn check_positive(
    key: &str,
    dist: Distribution,
    range: Option<(f64, f64)>,
    d_low: f64,
) -> Result<(), SensitivityError> {
    if d_low <= 0.0 && !matches!(dist, Distribution::LogNormal { .. } if d_low == 0.0) {
        let value = match range {
            Some((low, high)) => format!("[{low}, {high}]"),
            None => dist.name().to_string(),
        };
        let what = if range.is_some() { "range" } else { "dist" };
        return Err(config(
            format!("{key}: {what}"),
            value,
            format!(
                "draws values <= 0 ({} {}), and {key} must be positive: give a range with low > 0",
                dist.name(),
                describe_low(d_low)
            ),
        ));
    }
    Ok(())
}

impl Marginal {
    /// Checks `dist` (and `range`, the truncation, if given) for the input named `key`.
    ///
    /// Errors, each naming `key`, the parameter and its value: a parameter not finite; `low >=
    /// high`; `sd`, `sigma`, `median` or a loguniform `low` not `> 0`; `mode` outside `[low,
    /// high]`; a range that holds no mass of the distribution; and, with [`Domain::Positive`],
    /// any distribution whose draws can be `<= 0` (a normal without a range with `low > 0`, a
    /// uniform or triangular with `low <= 0`).
    pub fn new(
        key: &str,
        dist: Distribution,
        range: Option<(f64, f64)>,
        domain: Domain,
    ) -> Result<Marginal, SensitivityError> {
        check_parameters(key, dist, range)?;

        // The interval the draws fill: the support, cut to the range.
        let (s_low, s_high) = dist.support();
        let (d_low, d_high) = match range {
            Some((low, high)) => (low.max(s_low), high.min(s_high)),
            None => (s_low, s_high),
        };
        if domain == Domain::Positive {
            check_positive(key, dist, range, d_low)?;
        }

        let upper_tail = match dist {
            Distribution::Normal { mean, .. } => d_low > mean,
            Distribution::LogNormal { median, .. } => d_low > median,
            _ => false,
        };
        let mut m = Marginal {
            dist,
            range,
            p_start: 0.0,
            p_end: 1.0,
            upper_tail,
        };
        let (p_start, p_end) = (m.mass(d_low), m.mass(d_high));
        m.p_start = p_start;
        m.p_end = p_end;
        // In upper-tail coordinates the mass decreases along x.
        let width = (p_end - p_start).abs();
        if width.is_nan() || width <= 0.0 {
            let (low, high) = range.unwrap_or((d_low, d_high));
            return Err(config(
                format!("{key}: range"),
                format!("[{low}, {high}]"),
                format!(
                    "holds no probability of the {} distribution (too far in its tail or outside its support)",
                    dist.name()
                ),
            ));
        }
        Ok(m)
    }

    pub fn distribution(&self) -> Distribution {
        self.dist
    }

    /// The truncation, if any (as given, before it is cut to the support).
    pub fn range(&self) -> Option<(f64, f64)> {
        self.range
    }

    /// The mass coordinate of `x`: the untruncated CDF `F(x)`, or for a normal or lognormal in
    /// upper-tail mode its complement computed directly, `1 - F(x)`.
    fn mass(&self, x: f64) -> f64 {
        match self.dist {
            Distribution::Uniform { low, high } => ((x - low) / (high - low)).clamp(0.0, 1.0),
            Distribution::LogUniform { low, high } => {
                if x <= low {
                    0.0
                } else {
                    ((x / low).ln() / (high / low).ln()).clamp(0.0, 1.0)
                }
            }
            Distribution::Normal { mean, sd } => self.tail_mass((x - mean) / sd),
            Distribution::LogNormal { median, sigma } => {
                let z = if x <= 0.0 {
                    f64::NEG_INFINITY
                } else {
                    (x / median).ln() / sigma
                };
                self.tail_mass(z)
            }
            Distribution::Triangular { low, mode, high } => {
                if x <= low {
                    0.0
                } else if x >= high {
                    1.0
                } else if x <= mode {
                    (x - low) * (x - low) / ((high - low) * (mode - low))
                } else {
                    1.0 - (high - x) * (high - x) / ((high - low) * (high - mode))
                }
            }
        }
    }

    fn tail_mass(&self, z: f64) -> f64 {
        if self.upper_tail {
            normal::cdf(-z)
        } else {
            normal::cdf(z)
        }
    }

    /// The distribution's CDF with its truncation: the probability of a draw `<= x`.
    pub fn cdf(&self, x: f64) -> f64 {
        ((self.mass(x) - self.p_start) / (self.p_end - self.p_start)).clamp(0.0, 1.0)
    }

    /// The draw for the unit coordinate `u` in `[0, 1]`: the inverse of [`Marginal::cdf`],
    /// increasing in `u`, within the range. For a normal or lognormal `u` is held at `2⁻⁵³` from
    /// 0 and 1, so every draw is finite.
    pub fn quantile(&self, u: f64) -> f64 {
        let u = match self.dist {
            Distribution::Normal { .. } | Distribution::LogNormal { .. } => {
                u.clamp(P_TAIL, 1.0 - P_TAIL)
            }
            _ => u.clamp(0.0, 1.0),
        };
        let p = self.p_start + u * (self.p_end - self.p_start);
        let x = match self.dist {
            Distribution::Uniform { low, high } => low + p * (high - low),
            Distribution::LogUniform { low, high } => (low.ln() + p * (high / low).ln()).exp(),
            Distribution::Normal { mean, sd } => mean + sd * self.tail_quantile(p),
            Distribution::LogNormal { median, sigma } => {
                median * (sigma * self.tail_quantile(p)).exp()
            }
            Distribution::Triangular { low, mode, high } => {
                let split = (mode - low) / (high - low);
                if p < split {
                    low + (p * (high - low) * (mode - low)).sqrt()
                } else {
                    high - ((1.0 - p) * (high - low) * (high - mode)).sqrt()
                }
            }
        };
        // Rounding can step a hair outside the interval; the interval is a promise.
        let (s_low, s_high) = self.dist.support();
        let (low, high) = match self.range {
            Some((a, b)) => (a.max(s_low), b.min(s_high)),
            None => (s_low, s_high),
        };
        x.clamp(low, high)
    }

    /// `z` such that the mass coordinate of `z` is `p`.
    fn tail_quantile(&self, p: f64) -> f64 {
        if self.upper_tail {
            -normal::quantile(p)
        } else {
            normal::quantile(p)
        }
    }
}

fn describe_low(low: f64) -> String {
    if low == f64::NEG_INFINITY {
        "is unbounded below".to_string()
    } else {
        format!("reaches down to {low}")
    }
}
