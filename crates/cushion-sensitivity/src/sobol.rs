//! SALib's Sobol estimators (`SALib.analyze.sobol.analyze`, SALib 1.6) with their bootstrap
//! intervals, over many output columns at once. The formulas are in the crate's doc.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::error::{config, SensitivityError};
use crate::normal;
use crate::saltelli::block_len;

/// How to analyse: the layout the outputs were sampled in, and the bootstrap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SobolOptions {
    /// The outputs hold the `BA_j` rows (`2D + 2` rows per base point, else `D + 2`), and `S2`
    /// is estimated for every pair.
    pub second_order: bool,
    /// Bootstrap resamples of the base points (at least 2; SALib's default is 100).
    pub resamples: usize,
    /// The confidence level of the intervals, in `(0, 1)`.
    pub conf_level: f64,
    /// Seeds the resamples: the same outputs and seed give the same intervals.
    pub seed: u64,
}

impl Default for SobolOptions {
    fn default() -> Self {
        SobolOptions {
            second_order: true,
            resamples: 100,
            conf_level: 0.95,
            seed: 0,
        }
    }
}

/// An index and the half-width of its confidence interval (`value ± conf`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub conf: f64,
}

/// A second-order index of the inputs `j < k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairEstimate {
    pub j: usize,
    pub k: usize,
    pub value: f64,
    pub conf: f64,
}

/// The indices of one output that varies over the sample.
#[derive(Clone, Debug, PartialEq)]
pub struct SobolIndices {
    /// The output's mean and variance (`ddof = 0`) over every row of the sample, in its units.
    pub mean: f64,
    pub variance: f64,
    /// First-order index of each input.
    pub s1: Vec<Estimate>,
    /// Total index of each input.
    pub st: Vec<Estimate>,
    /// Second-order index of each pair `j < k`, in the order `(0,1), (0,2) .. (0,D-1), (1,2)
    /// ..`; empty without second order.
    pub s2: Vec<PairEstimate>,
}

/// What the analysis says of one output.
#[derive(Clone, Debug, PartialEq)]
pub enum Sensitivity {
    /// The output takes one value on every row: there is no variance to apportion (SALib would
    /// divide by zero and report NaN).
    Constant { value: f64 },
    /// The output varies: its indices.
    Indices(SobolIndices),
}

impl Sensitivity {
    /// The indices, unless the output is constant.
    pub fn indices(&self) -> Option<&SobolIndices> {
        match self {
            Sensitivity::Constant { .. } => None,
            Sensitivity::Indices(s) => Some(s),
        }
    }
}

/// Resamples drawn together: one matrix product per column gives their sums. Fixed, so the
/// result does not depend on the thread count.
const BATCH: usize = 64;

/// SALib's threshold for a zero range or variance (`np.finfo(float).eps`).
const EPS: f64 = f64::EPSILON;

/// One output column, normalised as SALib does and checked.
struct Column {
    /// The terms of each base point (see [`Layout::n_terms`]) of the normalised output, `N`
    /// rows of `n_terms`.
    terms: Vec<f64>,
    mean: f64,
    variance: f64,
    /// The normalised `A` and `B` rows span no more than `EPS`: SALib returns 0 for every index
    /// and every interval.
    flat_ab: bool,
}

/// The shape shared by every column.
#[derive(Clone, Copy)]
struct Layout {
    d: usize,
    block: usize,
    n: usize,
    second_order: bool,
}

impl Layout {
    fn n_pairs(&self) -> usize {
        if self.second_order {
            self.d * (self.d - 1) / 2
        } else {
            0
        }
    }

    /// Estimates per resample: `S1` of each input, `ST` of each input, `S2` of each pair.
    fn n_estimates(&self) -> usize {
        2 * self.d + self.n_pairs()
    }

    /// Every estimate is a ratio of means over the base points; the terms of one base point,
    /// from its normalised outputs `a, b, ab_j, ba_j`: `a + b`, `a² + b²`, `b (ab_j - a)` for
    /// each `j`, `(a - ab_j)²` for each `j`, `ba_j ab_k - a b` for each pair.
    fn n_terms(&self) -> usize {
        2 + self.n_estimates()
    }
}

/// Sobol indices of every column of `outputs`, each a model output over a Saltelli sample of
/// `n_inputs` inputs in SALib's row order (see [`crate::SaltelliSample`]): `S1`, `ST` and with
/// `options.second_order` `S2`, each with its bootstrap interval, or [`Sensitivity::Constant`].
/// One result per column, in order.
///
/// Parallel over columns and resamples on the current rayon pool; the result does not depend on
/// the number of threads (every resample draws from its own seeded stream, and nothing is summed
/// across threads). Every column is resampled with the same base points, as SALib would with one
/// seed.
///
/// Errors: `n_inputs` 0; `resamples < 2`; `conf_level` outside `(0, 1)`; a column whose length
/// is not a positive multiple of the block (`2D + 2` or `D + 2`) or differs from the first's; a
/// value not finite (the error names the column and the row).
pub fn analyze(
    n_inputs: usize,
    outputs: &[&[f64]],
    options: &SobolOptions,
) -> Result<Vec<Sensitivity>, SensitivityError> {
    let Some(layout) = check(n_inputs, outputs, options)? else {
        return Ok(Vec::new());
    };
    let columns: Vec<Option<Column>> = outputs
        .par_iter()
        .enumerate()
        .map(|(o, y)| prepare(o, y, &layout))
        .collect::<Result<_, _>>()?;
    let points = point_estimates(&columns, &layout);
    let boot_columns: Vec<&Column> = columns.iter().flatten().filter(|c| !c.flat_ab).collect();
    let boot = bootstrap(&boot_columns, &layout, options);
    let z = normal::quantile(0.5 + options.conf_level / 2.0);
    let per_resample = boot_columns.len() * layout.n_estimates();
    let mut boot_column = 0;
    let mut results = Vec::with_capacity(columns.len());
    for (o, (column, point)) in columns.iter().zip(points).enumerate() {
        let (Some(column), Some(point)) = (column, point) else {
            results.push(Sensitivity::Constant {
                value: outputs[o][0],
            });
            continue;
        };
        let conf: Vec<f64> = if column.flat_ab {
            vec![0.0; layout.n_estimates()]
        } else {
            let at = boot_column * layout.n_estimates();
            boot_column += 1;
            (0..layout.n_estimates())
                .map(|e| z * std_ddof1(boot.iter().skip(at + e).step_by(per_resample).copied()))
                .collect()
        };
        results.push(Sensitivity::Indices(indices(
            column, &point, &conf, &layout,
        )));
    }
    Ok(results)
}

/// The options and the columns' shape checked; the layout, or `None` without columns.
fn check(
    n_inputs: usize,
    outputs: &[&[f64]],
    options: &SobolOptions,
) -> Result<Option<Layout>, SensitivityError> {
    if n_inputs == 0 {
        return Err(config("inputs", n_inputs, "must be at least 1"));
    }
    if options.resamples < 2 {
        return Err(config(
            "resamples",
            options.resamples,
            "must be at least 2 (the interval is their standard deviation)",
        ));
    }
    if !(options.conf_level > 0.0 && options.conf_level < 1.0) {
        return Err(config(
            "conf_level",
            options.conf_level,
            "must lie strictly between 0 and 1",
        ));
    }
    let block = block_len(n_inputs, options.second_order);
    let Some(first) = outputs.first() else {
        return Ok(None);
    };
    let rows = first.len();
    for (o, y) in outputs.iter().enumerate() {
        if y.is_empty() || y.len() % block != 0 {
            return Err(SensitivityError::Output {
                output: o,
                problem: format!(
                    "{} values: a Saltelli sample of {n_inputs} inputs {} second order has a positive multiple of {block} rows",
                    y.len(),
                    if options.second_order { "with" } else { "without" },
                ),
            });
        }
        if y.len() != rows {
            return Err(SensitivityError::Output {
                output: o,
                problem: format!("{} values, output 0 has {rows}", y.len()),
            });
        }
    }
    Ok(Some(Layout {
        d: n_inputs,
        block,
        n: rows / block,
        second_order: options.second_order,
    }))
}

/// Point estimates on the sample itself, every base point once; `None` for a constant column.
fn point_estimates(columns: &[Option<Column>], layout: &Layout) -> Vec<Option<Vec<f64>>> {
    columns
        .par_iter()
        .map(|c| {
            c.as_ref().map(|c| {
                let mut sums = vec![0.0; layout.n_terms()];
                for q in c.terms.chunks_exact(layout.n_terms()) {
                    for (s, v) in sums.iter_mut().zip(q) {
                        *s += v;
                    }
                }
                let mut out = vec![0.0; layout.n_estimates()];
                if !c.flat_ab {
                    estimates_from_sums(&sums, layout.n as f64, layout, &mut out);
                }
                out
            })
        })
        .collect()
}

/// Every resample's estimates of every column, laid out [resample][column][estimate]: in
/// batches of resamples, each batch drawing its resamples' base points (resample b from its own
/// stream), then weighting base point i by how often each resample drew it.
fn bootstrap(columns: &[&Column], layout: &Layout, options: &SobolOptions) -> Vec<f64> {
    let per_resample = columns.len() * layout.n_estimates();
    let mut boot = vec![0.0; options.resamples * per_resample];
    if per_resample == 0 {
        return boot;
    }
    let (n, t) = (layout.n, layout.n_terms());
    // Every column's terms side by side, row i holding base point i's: one matrix product per
    // batch then gives every resample's sums of every column.
    let width = columns.len() * t;
    let mut terms = vec![0.0; n * width];
    for (c, column) in columns.iter().enumerate() {
        for (row, q) in terms
            .chunks_exact_mut(width)
            .zip(column.terms.chunks_exact(t))
        {
            row[c * t..(c + 1) * t].copy_from_slice(q);
        }
    }
    boot.par_chunks_mut(BATCH * per_resample)
        .enumerate()
        .for_each(|(batch, out)| {
            let nb = out.len() / per_resample;
            // counts[b * n + i]: draws of base point i in the batch's resample b (each resample
            // from its own stream, so batches do not change the draws).
            let mut counts = vec![0.0f64; nb * n];
            for (b, row) in counts.chunks_exact_mut(n).enumerate() {
                let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
                rng.set_stream((batch * BATCH + b) as u64);
                for _ in 0..n {
                    row[rng.random_range(0..n)] += 1.0;
                }
            }
            let mut sums = vec![0.0; nb * width];
            weighted_sums(&counts, nb, n, &terms, width, &mut sums);
            for (b, row) in sums.chunks_exact(width).enumerate() {
                for (c, q) in row.chunks_exact(t).enumerate() {
                    let at = b * per_resample + c * layout.n_estimates();
                    let e = layout.n_estimates();
                    estimates_from_sums(q, n as f64, layout, &mut out[at..at + e]);
                }
            }
        });
    boot
}

/// One column's indices from its point estimates and interval half-widths (both in the order
/// of [`Layout::n_estimates`]).
fn indices(column: &Column, point: &[f64], conf: &[f64], layout: &Layout) -> SobolIndices {
    let d = layout.d;
    let est = |e: usize| Estimate {
        value: point[e],
        conf: conf[e],
    };
    let mut s2 = Vec::with_capacity(layout.n_pairs());
    if layout.second_order {
        let mut e = 2 * d;
        for j in 0..d {
            for k in j + 1..d {
                s2.push(PairEstimate {
                    j,
                    k,
                    value: point[e],
                    conf: conf[e],
                });
                e += 1;
            }
        }
    }
    SobolIndices {
        mean: column.mean,
        variance: column.variance,
        s1: (0..d).map(est).collect(),
        st: (d..2 * d).map(est).collect(),
        s2,
    }
}

/// `sums = counts · terms`: the sums of each resample's terms weighted by its draws (`counts`
/// is `nb x n`, `terms` is `n x t`, `sums` is `nb x t`, all row-major). One single-threaded
/// matrix product, so its rounding does not depend on the thread count.
fn weighted_sums(counts: &[f64], nb: usize, n: usize, terms: &[f64], t: usize, sums: &mut [f64]) {
    assert!(counts.len() == nb * n && terms.len() == n * t && sums.len() == nb * t);
    // SAFETY: the three slices hold the row-major matrices the strides describe (asserted
    // above), and `sums` is borrowed mutably, so it aliases neither input.
    unsafe {
        matrixmultiply::dgemm(
            nb,
            n,
            t,
            1.0,
            counts.as_ptr(),
            n as isize,
            1,
            terms.as_ptr(),
            t as isize,
            1,
            0.0,
            sums.as_mut_ptr(),
            t as isize,
            1,
        );
    }
}

/// Checks a column and normalises it as SALib does, `Y = (Y - Y.mean()) / Y.std()`; `None`
/// for a constant column.
fn prepare(o: usize, y: &[f64], layout: &Layout) -> Result<Option<Column>, SensitivityError> {
    if let Some((row, v)) = y.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SensitivityError::Output {
            output: o,
            problem: format!("row {row} is {v}: the estimators need finite values"),
        });
    }
    if y.iter().all(|v| *v == y[0]) {
        return Ok(None);
    }
    // Compensated sums, so the centring is as exact as NumPy's (which S1 and S2, unlike ST,
    // depend on).
    let mean = neumaier(y.iter().copied()) / y.len() as f64;
    let variance = neumaier(y.iter().map(|v| (v - mean) * (v - mean))) / y.len() as f64;
    let sd = variance.sqrt();
    let d = layout.d;
    let mut terms = Vec::with_capacity(layout.n * layout.n_terms());
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut blk = vec![0.0; layout.block];
    for raw in y.chunks_exact(layout.block) {
        for (x, v) in blk.iter_mut().zip(raw) {
            *x = (v - mean) / sd;
        }
        let a = blk[0];
        let b = blk[layout.block - 1];
        lo = lo.min(a).min(b);
        hi = hi.max(a).max(b);
        let ab = &blk[1..=d];
        terms.push(a + b);
        terms.push(a * a + b * b);
        terms.extend(ab.iter().map(|x| b * (x - a)));
        terms.extend(ab.iter().map(|x| (a - x) * (a - x)));
        if layout.second_order {
            let ba = &blk[d + 1..=2 * d];
            for (j, ba_j) in ba.iter().enumerate() {
                terms.extend(ab[j + 1..].iter().map(|ab_k| ba_j * ab_k - a * b));
            }
        }
    }
    Ok(Some(Column {
        terms,
        mean,
        variance,
        flat_ab: hi - lo <= EPS,
    }))
}

/// `S1_j`, `ST_j` and `S2_jk` (see [`Layout::n_estimates`]) from the sums of the terms over
/// `n` base points (SALib's `first_order`, `total_order` and `second_order`).
fn estimates_from_sums(sums: &[f64], n: f64, layout: &Layout, out: &mut [f64]) {
    let d = layout.d;
    // np.var(np.r_[A, B]): ddof 0 over the 2n values. From the sums of a + b and a² + b²: the
    // column is normalised (mean near 0, spread near 1), so nothing cancels.
    let m = sums[0] / (2.0 * n);
    let var = sums[1] / (2.0 * n) - m * m;
    // SALib divides only where the variance exceeds eps, and gives 0 elsewhere.
    let ratio = |x: f64| if var > EPS { x / n / var } else { 0.0 };
    for j in 0..d {
        out[j] = ratio(sums[2 + j]);
        out[d + j] = 0.5 * ratio(sums[2 + d + j]);
    }
    if layout.second_order {
        let mut p = 2 * d;
        for j in 0..d {
            for k in j + 1..d {
                out[p] = ratio(sums[2 + p]) - out[j] - out[k];
                p += 1;
            }
        }
    }
}

/// NumPy's `std(ddof=1)`, two passes.
fn std_ddof1(x: impl Iterator<Item = f64> + Clone) -> f64 {
    let n = x.clone().count() as f64;
    let mean = x.clone().sum::<f64>() / n;
    (x.map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Neumaier's compensated sum.
fn neumaier(x: impl Iterator<Item = f64>) -> f64 {
    let mut sum = 0.0;
    let mut c = 0.0;
    for v in x {
        let t = sum + v;
        if sum.abs() >= v.abs() {
            c += (sum - t) + v;
        } else {
            c += (v - t) + sum;
        }
        sum = t;
    }
    sum + c
}
