//! From run number to axis values: grid, zip, Latin hypercube (seeded ChaCha8), Sobol
//! (Owen-scrambled, seeded, `sobol_burley`) and Saltelli (SALib's layout over a scrambled Sobol
//! sequence, `cushion_sensitivity::SaltelliSample`). A `range` axis maps its unit coordinate
//! `u` onto its range (uniformly, or log-uniformly), or through its distribution's inverse CDF
//! (`Marginal::quantile`). Every point is a pure function of the sweep file
//! and the run number, so any subset of runs (a chunk, a shard, a resumed remainder) gets the
//! same values as a full run, on any number of threads.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use toml::Value;

use crate::sweep_file::{Axis, AxisValues, Mode, SweepFile};
use cushion_model::Scene;
use cushion_sensitivity::{Marginal, SaltelliSample};

/// The largest Latin hypercube (its strata hold 4 bytes per run and axis).
pub const LHS_MAX_SAMPLES: u64 = 1 << 27;

/// The sampling plan of a sweep file.
#[derive(Clone, Debug)]
pub struct Design {
    mode: Mode,
    axes: Vec<Axis>,
    /// Per axis, its distribution beyond uniform and loguniform.
    marginals: Vec<Option<Marginal>>,
    /// saltelli only.
    saltelli: Option<SaltelliSample>,
    n_runs: u64,
    seed: u64,
    /// Latin hypercube: for each axis, the stratum of each run (a permutation of `0..n`).
    strata: Vec<Vec<u32>>,
}

/// A uniform number in [0, 1) with 53 random bits.
fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl Design {
    pub fn new(sweep: &SweepFile) -> Result<Design, String> {
        let n_runs = sweep.n_runs()?;
        let mut strata = Vec::new();
        if sweep.mode == Mode::Lhs {
            // The strata take 4 bytes per run and axis.
            if n_runs > LHS_MAX_SAMPLES {
                return Err(format!(
                    "[sampling] samples = {n_runs}: lhs takes at most {LHS_MAX_SAMPLES} samples"
                ));
            }
            for d in 0..sweep.axes.len() {
                // Fisher-Yates with its own stream per axis.
                let mut rng = ChaCha8Rng::seed_from_u64(sweep.seed);
                rng.set_stream(2 * d as u64 + 1);
                let mut perm: Vec<u32> = (0..n_runs as u32).collect();
                for i in (1..perm.len()).rev() {
                    let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                    perm.swap(i, j);
                }
                strata.push(perm);
            }
        }
        let saltelli = if sweep.mode == Mode::Saltelli {
            Some(
                SaltelliSample::new(
                    sweep.axes.len(),
                    sweep.samples as usize,
                    sweep.second_order,
                    sweep.seed,
                )
                .map_err(|e| format!("[sampling] {e}"))?,
            )
        } else {
            None
        };
        let mut marginals = sweep.marginals.clone();
        marginals.resize(sweep.axes.len(), None);
        Ok(Design {
            mode: sweep.mode,
            axes: sweep.axes.clone(),
            marginals,
            saltelli,
            n_runs,
            seed: sweep.seed,
            strata,
        })
    }

    pub fn n_runs(&self) -> u64 {
        self.n_runs
    }

    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// The Saltelli sample (saltelli mode only).
    pub fn saltelli(&self) -> Option<&SaltelliSample> {
        self.saltelli.as_ref()
    }

    /// Axis `d`'s value for the unit coordinate `u` (a range axis).
    fn map_range(&self, d: usize, u: f64) -> Value {
        if let Some(m) = &self.marginals[d] {
            return Value::Float(m.quantile(u));
        }
        let AxisValues::Range { low, high, log } = &self.axes[d].values else {
            unreachable!("map_range on a list axis")
        };
        let x = if *log {
            (low.ln() + u * (high.ln() - low.ln())).exp()
        } else {
            low + u * (high - low)
        };
        Value::Float(x.clamp(*low, *high))
    }

    /// The unit-cube coordinate of `run` on axis `d` (lhs and sobol).
    fn unit_coord(&self, run: u64, d: usize) -> f64 {
        match self.mode {
            Mode::Lhs => {
                // Jitter inside the stratum: one ChaCha8 word pair per (axis, run).
                let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
                rng.set_stream(2 * d as u64 + 2);
                rng.set_word_pos(2 * run as u128);
                let u = unit(rng.next_u64());
                let u = (self.strata[d][run as usize] as f64 + u) / self.n_runs as f64;
                u.min(1.0 - f64::EPSILON / 2.0)
            }
            Mode::Sobol => sobol_burley::sample(run as u32, d as u32, self.seed as u32) as f64,
            Mode::Grid | Mode::Zip | Mode::Saltelli => {
                unreachable!("grid, zip and saltelli have no per-axis unit coordinates")
            }
        }
    }

    /// The axis values of one run, one per axis, in axis order.
    pub fn point(&self, run: u64) -> Vec<Value> {
        assert!(run < self.n_runs, "run {run} out of 0..{}", self.n_runs);
        match self.mode {
            Mode::Grid => {
                let mut rest = run;
                let mut out = vec![Value::Boolean(false); self.axes.len()];
                for (d, a) in self.axes.iter().enumerate().rev() {
                    let AxisValues::List(vals) = &a.values else {
                        unreachable!()
                    };
                    let k = vals.len() as u64;
                    out[d] = vals[(rest % k) as usize].clone();
                    rest /= k;
                }
                out
            }
            Mode::Zip => self
                .axes
                .iter()
                .map(|a| {
                    let AxisValues::List(vals) = &a.values else {
                        unreachable!()
                    };
                    vals[run as usize].clone()
                })
                .collect(),
            Mode::Lhs | Mode::Sobol => self
                .axes
                .iter()
                .enumerate()
                .map(|(d, a)| {
                    let u = self.unit_coord(run, d);
                    match &a.values {
                        AxisValues::List(vals) => {
                            let k = vals.len();
                            vals[((u * k as f64) as usize).min(k - 1)].clone()
                        }
                        AxisValues::Range { .. } => self.map_range(d, u),
                    }
                })
                .collect(),
            Mode::Saltelli => {
                let sample = self
                    .saltelli
                    .as_ref()
                    .expect("saltelli mode has its sample");
                sample
                    .unit_point(run)
                    .into_iter()
                    .enumerate()
                    .map(|(d, u)| self.map_range(d, u))
                    .collect()
            }
        }
    }

    /// The scene of one run: the base scene with the run's axis values set (not validated).
    pub fn scene(&self, base: &Scene, point: &[Value]) -> Result<Scene, String> {
        let mut scene = base.clone();
        for (a, v) in self.axes.iter().zip(point) {
            scene.set(&a.key, v).map_err(|e| e.to_string())?;
        }
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn design(text: &str) -> Design {
        let s = SweepFile::from_str_at(text, Path::new("/x/t.toml")).unwrap();
        Design::new(&s).unwrap()
    }

    #[test]
    fn grid_is_row_major() {
        let d = design(
            "[[axis]]\nkey = \"robot.dead_time\"\nvalues = [1, 2]\n[[axis]]\nkey = \"object.mass\"\nvalues = [10, 20, 30]\n",
        );
        assert_eq!(d.n_runs(), 6);
        let pts: Vec<_> = (0..6).map(|r| d.point(r)).collect();
        assert_eq!(pts[0], vec![Value::Integer(1), Value::Integer(10)]);
        assert_eq!(pts[1], vec![Value::Integer(1), Value::Integer(20)]);
        assert_eq!(pts[5], vec![Value::Integer(2), Value::Integer(30)]);
    }

    #[test]
    fn lhs_is_stratified_and_seeded() {
        let text = "[sampling]\nmode = \"lhs\"\nsamples = 50\nseed = 3\n[[axis]]\nkey = \"object.mass\"\nrange = [0.0, 1.0]\n[[axis]]\nkey = \"hydraulic.gas_pressure\"\nrange = [300, 1e5]\nscale = \"log\"\n[[axis]]\nkey = \"module\"\nvalues = [\"hydraulic\", \"bistable\"]\n";
        let d = design(text);
        let d2 = design(text);
        let mut strata = [false; 50];
        let mut hydraulic = 0;
        for r in 0..50 {
            let p = d.point(r);
            assert_eq!(p, d2.point(r));
            let m = p[0].as_float().unwrap();
            assert!((0.0..1.0).contains(&m));
            strata[(m * 50.0) as usize] = true;
            let g = p[1].as_float().unwrap();
            assert!((300.0..=1e5).contains(&g));
            if p[2].as_str() == Some("hydraulic") {
                hydraulic += 1;
            }
        }
        assert!(strata.iter().all(|s| *s), "one sample per stratum");
        assert_eq!(hydraulic, 25, "categorical values drawn evenly");
        let other = design(&text.replace("seed = 3", "seed = 4"));
        assert_ne!(other.point(0), d.point(0));
    }

    #[test]
    fn sobol_in_range_and_balanced() {
        let d = design("[sampling]\nmode = \"sobol\"\nsamples = 64\nseed = 1\n[[axis]]\nkey = \"object.mass\"\nrange = [0.05, 1.0]\n[[axis]]\nkey = \"module\"\nvalues = [\"hydraulic\", \"bistable\"]\n");
        let mut h = 0;
        for r in 0..64 {
            let p = d.point(r);
            let m = p[0].as_float().unwrap();
            assert!((0.05..=1.0).contains(&m));
            if p[1].as_str() == Some("hydraulic") {
                h += 1;
            }
        }
        assert_eq!(h, 32);
    }

    #[test]
    fn saltelli_rows_are_the_sample_mapped_through_the_axes() {
        for second_order in [true, false] {
            let text = format!(
                "[sampling]\nmode = \"saltelli\"\nsamples = 16\nseed = 5\nsecond_order = {second_order}\n[[axis]]\nkey = \"robot.dead_time\"\nrange = [0.01, 0.1]\n[[axis]]\nkey = \"hydraulic.gas_pressure\"\nrange = [300, 1e5]\nscale = \"log\"\n[[axis]]\nkey = \"object.mass\"\nrange = [0.05, 1.0]\ndist = \"triangular\"\nmode = 0.2\n"
            );
            let d = design(&text);
            let s = SaltelliSample::new(3, 16, second_order, 5).unwrap();
            assert_eq!(d.n_runs(), s.n_rows());
            assert_eq!(d.n_runs(), 16 * if second_order { 8 } else { 5 });
            let tri = Marginal::new(
                "object.mass",
                cushion_sensitivity::Distribution::Triangular {
                    low: 0.05,
                    mode: 0.2,
                    high: 1.0,
                },
                None,
                cushion_sensitivity::Domain::Real,
            )
            .unwrap();
            for r in 0..d.n_runs() {
                let u = s.unit_point(r);
                let p: Vec<f64> = d.point(r).iter().map(|v| v.as_float().unwrap()).collect();
                assert_eq!(
                    p[0],
                    (0.01 + u[0] * (0.1 - 0.01)).clamp(0.01, 0.1),
                    "run {r}"
                );
                let g = (300f64.ln() + u[1] * (1e5f64.ln() - 300f64.ln())).exp();
                assert_eq!(p[1], g.clamp(300.0, 1e5), "run {r}");
                assert_eq!(p[2], tri.quantile(u[2]), "run {r}");
            }
        }
    }

    #[test]
    fn loguniform_is_scale_log_to_the_bit() {
        let a = design("[sampling]\nmode = \"lhs\"\nsamples = 64\nseed = 9\n[[axis]]\nkey = \"hydraulic.gas_pressure\"\nrange = [300, 1e5]\nscale = \"log\"\n");
        let b = design("[sampling]\nmode = \"lhs\"\nsamples = 64\nseed = 9\n[[axis]]\nkey = \"hydraulic.gas_pressure\"\nrange = [300, 1e5]\ndist = \"loguniform\"\n");
        for r in 0..64 {
            assert_eq!(a.point(r), b.point(r));
        }
    }

    /// The largest distance between the sample's empirical CDF and `cdf`.
    fn ks(mut xs: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
        xs.sort_by(f64::total_cmp);
        let n = xs.len() as f64;
        xs.iter()
            .enumerate()
            .map(|(i, &x)| {
                let f = cdf(x);
                (f - i as f64 / n).abs().max((f - (i + 1) as f64 / n).abs())
            })
            .fold(0.0, f64::max)
    }

    fn column(d: &Design, axis: usize) -> Vec<f64> {
        (0..d.n_runs())
            .map(|r| d.point(r)[axis].as_float().unwrap())
            .collect()
    }

    #[test]
    fn distributions_follow_their_cdf_and_truncation_holds() {
        use cushion_sensitivity::normal::cdf as phi;
        let n = 4096;
        for mode in ["sobol", "lhs"] {
            let d = design(&format!(
                "[sampling]\nmode = \"{mode}\"\nsamples = {n}\nseed = 2\n\
                 [[axis]]\nkey = \"robot.dead_time\"\ndist = \"normal\"\nmean = 0.07\nsd = 0.01\nrange = [0.05, 0.1]\n\
                 [[axis]]\nkey = \"object.mass\"\ndist = \"lognormal\"\nmedian = 0.2\nsigma = 0.5\n\
                 [[axis]]\nkey = \"hydraulic.orifice_radius\"\ndist = \"triangular\"\nrange = [0.0005, 0.002]\nmode = 0.001\n\
                 [[axis]]\nkey = \"tool.viscous_friction\"\ndist = \"normal\"\nmean = 5\nsd = 2\nrange = [-1000, 1000]\n"
            ));
            // The Kolmogorov-Smirnov bound at 99.9 % for independent draws; low-discrepancy
            // points do much better.
            let bound = 1.95 / (n as f64).sqrt();
            let dt = column(&d, 0);
            assert!(dt.iter().all(|x| (0.05..=0.1).contains(x)), "truncation");
            let (lo, hi) = (phi((0.05 - 0.07) / 0.01), phi((0.1 - 0.07) / 0.01));
            let k = ks(dt.clone(), |x| (phi((x - 0.07) / 0.01) - lo) / (hi - lo));
            assert!(k < bound, "{mode} truncated normal: KS {k}");
            let m = column(&d, 1);
            assert!(m.iter().all(|x| *x > 0.0));
            let k = ks(m.clone(), |x| phi((x / 0.2).ln() / 0.5));
            assert!(k < bound, "{mode} lognormal: KS {k}");
            let mut sorted = m.clone();
            sorted.sort_by(f64::total_cmp);
            let median = sorted[n / 2];
            assert!((median / 0.2 - 1.0).abs() < 0.01, "median {median}");
            let r = column(&d, 2);
            assert!(r.iter().all(|x| (0.0005..=0.002).contains(x)));
            let tri = |x: f64| {
                let (a, c, b) = (0.0005, 0.001, 0.002);
                if x <= c {
                    (x - a) * (x - a) / ((b - a) * (c - a))
                } else {
                    1.0 - (b - x) * (b - x) / ((b - a) * (b - c))
                }
            };
            let k = ks(r, tri);
            assert!(k < bound, "{mode} triangular: KS {k}");
            let v = column(&d, 3);
            let mean = v.iter().sum::<f64>() / n as f64;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
            assert!(
                (mean - 5.0).abs() < 0.01 && (sd / 2.0 - 1.0).abs() < 0.01,
                "{mean} {sd}"
            );
            let k = ks(v, |x| phi((x - 5.0) / 2.0));
            assert!(k < bound, "{mode} normal: KS {k}");
        }
    }
}
