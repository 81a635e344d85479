//! Input distributions: quantiles against SciPy and closed forms, moments of a Sobol column,
//! a Kolmogorov-Smirnov bound for independent draws, truncation, and the validation messages.

use cushion_sensitivity::{Distribution, Domain, Marginal, SaltelliSample, SensitivityError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use Distribution::*;

fn marginal(dist: Distribution, range: Option<(f64, f64)>) -> Marginal {
    Marginal::new("x", dist, range, Domain::Real).unwrap()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol * want.abs().max(1.0),
        "{what}: got {got}, want {want} (tolerance {tol:e})"
    );
}

/// Every distribution the tests sample, with a truncation or not.
fn cases() -> Vec<(&'static str, Marginal)> {
    vec![
        (
            "uniform",
            marginal(
                Uniform {
                    low: -2.0,
                    high: 3.0,
                },
                None,
            ),
        ),
        (
            "uniform cut",
            marginal(
                Uniform {
                    low: -2.0,
                    high: 3.0,
                },
                Some((0.0, 10.0)),
            ),
        ),
        (
            "loguniform",
            marginal(
                LogUniform {
                    low: 0.01,
                    high: 100.0,
                },
                None,
            ),
        ),
        (
            "normal",
            marginal(
                Normal {
                    mean: 0.07,
                    sd: 0.01,
                },
                None,
            ),
        ),
        (
            "normal cut",
            marginal(Normal { mean: 0.0, sd: 1.0 }, Some((-1.0, 2.0))),
        ),
        (
            "normal far tail",
            marginal(Normal { mean: 0.0, sd: 1.0 }, Some((10.0, 11.0))),
        ),
        (
            "lognormal",
            marginal(
                LogNormal {
                    median: 2.0,
                    sigma: 0.5,
                },
                None,
            ),
        ),
        (
            "lognormal cut",
            marginal(
                LogNormal {
                    median: 2.0,
                    sigma: 0.5,
                },
                Some((1.0, 3.0)),
            ),
        ),
        (
            "triangular",
            marginal(
                Triangular {
                    low: 1.0,
                    mode: 2.0,
                    high: 5.0,
                },
                None,
            ),
        ),
        (
            "triangular mode at low",
            marginal(
                Triangular {
                    low: 0.0,
                    mode: 0.0,
                    high: 1.0,
                },
                None,
            ),
        ),
        (
            "triangular mode at high, cut",
            marginal(
                Triangular {
                    low: 0.0,
                    mode: 1.0,
                    high: 1.0,
                },
                Some((0.5, 2.0)),
            ),
        ),
    ]
}

#[test]
fn quantiles_match_scipy_and_closed_forms() {
    let z975 = 1.959963984540054;
    let n = marginal(
        Normal {
            mean: 0.07,
            sd: 0.01,
        },
        None,
    );
    close(
        n.quantile(0.975),
        0.07 + 0.01 * z975,
        1e-15,
        "normal 97.5 %",
    );
    close(n.quantile(0.5), 0.07, 1e-15, "normal median");
    let ln = marginal(
        LogNormal {
            median: 2.0,
            sigma: 0.5,
        },
        None,
    );
    close(ln.quantile(0.5), 2.0, 1e-15, "lognormal median");
    close(ln.quantile(0.9), 3.795905414669421, 1e-14, "lognormal 90 %");
    let lu = marginal(
        LogUniform {
            low: 0.01,
            high: 100.0,
        },
        None,
    );
    close(lu.quantile(0.5), 1.0, 1e-14, "loguniform median");
    close(lu.quantile(0.25), 0.1, 1e-14, "loguniform quartile");
    let t = marginal(
        Triangular {
            low: 1.0,
            mode: 2.0,
            high: 5.0,
        },
        None,
    );
    close(t.quantile(0.25), 2.0, 1e-15, "triangular: F(mode) = 1/4");
    close(
        t.quantile(0.2),
        1.8944271909999157,
        1e-15,
        "triangular 20 %",
    );
    close(t.quantile(0.7), 3.102633403898972, 1e-15, "triangular 70 %");
    // scipy.stats.truncnorm
    let tn = marginal(Normal { mean: 0.0, sd: 1.0 }, Some((-1.0, 2.0)));
    close(
        tn.quantile(0.3),
        -0.2424038178892269,
        1e-14,
        "truncnorm(-1, 2) 30 %",
    );
    let far = marginal(Normal { mean: 0.0, sd: 1.0 }, Some((10.0, 11.0)));
    close(
        far.quantile(0.5),
        10.068409369547618,
        1e-14,
        "truncnorm(10, 11) median",
    );
    close(
        far.quantile(0.9),
        10.225504949376699,
        1e-14,
        "truncnorm(10, 11) 90 %",
    );
    let lc = marginal(
        LogNormal {
            median: 2.0,
            sigma: 0.5,
        },
        Some((1.0, 3.0)),
    );
    close(
        lc.quantile(0.25),
        1.4497494183323993,
        1e-14,
        "lognormal on [1, 3], 25 %",
    );
}

#[test]
fn truncation_holds_and_quantile_inverts_cdf() {
    for (name, m) in cases() {
        let (low, high) = match m.range() {
            Some((a, b)) => {
                let (s, t) = m.distribution().support();
                (a.max(s), b.min(t))
            }
            None => m.distribution().support(),
        };
        let mut last = f64::NEG_INFINITY;
        for k in 0..=1000 {
            let u = k as f64 / 1000.0;
            let x = m.quantile(u);
            assert!(x.is_finite(), "{name}: quantile({u}) = {x}");
            assert!(x >= low && x <= high, "{name}: {x} outside [{low}, {high}]");
            assert!(x >= last, "{name}: quantile decreases at u = {u}");
            last = x;
            if k > 0 && k < 1000 {
                close(m.cdf(x), u, 1e-12, &format!("{name}: cdf(quantile({u}))"));
            }
        }
        if m.range().is_some() {
            // The ends of the range are the ends of the draws, and hold no mass beyond.
            close(m.quantile(0.0), low, 1e-12, &format!("{name}: lowest draw"));
            close(
                m.quantile(1.0),
                high,
                1e-12,
                &format!("{name}: highest draw"),
            );
            assert_eq!(m.cdf(low), 0.0, "{name}");
            assert_eq!(m.cdf(high), 1.0, "{name}");
        }
    }
    // Unbounded tails stop 8.2 standard deviations out (a mass of 2^-53).
    let n = marginal(Normal { mean: 0.0, sd: 1.0 }, None);
    close(
        n.quantile(1.0),
        8.209536151601387,
        1e-14,
        "highest normal draw",
    );
    close(
        n.quantile(0.0),
        -8.209536151601387,
        1e-14,
        "lowest normal draw",
    );
}

/// Kolmogorov-Smirnov: 4096 independent draws (ChaCha8) through each quantile, against the
/// CDF. At the 0.1 % level the statistic of a correct sampler stays below 1.949 / √n.
#[test]
fn kolmogorov_smirnov_of_independent_draws() {
    let n = 4096;
    let bound = 1.949 / (n as f64).sqrt();
    for (i, (name, m)) in cases().into_iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(56);
        rng.set_stream(i as u64);
        let mut x: Vec<f64> = (0..n)
            .map(|_| m.quantile((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64))
            .collect();
        x.sort_by(f64::total_cmp);
        let d = x
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                let f = m.cdf(v);
                (f - k as f64 / n as f64).max((k + 1) as f64 / n as f64 - f)
            })
            .fold(0.0, f64::max);
        assert!(d < bound, "{name}: KS statistic {d} >= {bound}");
    }
}

/// Mean and standard deviation of one Saltelli column (2^14 Sobol points, stratified) mapped
/// through each distribution, against closed forms. The stratification makes them far more
/// accurate than independent draws would be (whose standard error is sd/128 = 0.8 % of sd):
/// the bound asked is 0.1 % of sd.
#[test]
fn moments_of_a_sobol_column() {
    let s = SaltelliSample::new(2, 1 << 14, false, 11).unwrap();
    let u: Vec<f64> = (0..s.n_base()).map(|i| s.base_coord(i, 1)).collect();
    let phi = |z: f64| (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let big_phi = cushion_sensitivity::normal::cdf;
    // Truncated standard normal on [a, b]: mean and variance.
    let (a, b) = (-1.0, 2.0);
    let zm = big_phi(b) - big_phi(a);
    let tn_mean = (phi(a) - phi(b)) / zm;
    let tn_var = 1.0 + (a * phi(a) - b * phi(b)) / zm - tn_mean * tn_mean;
    close(
        tn_mean,
        0.22963717909132902,
        1e-14,
        "truncnorm mean (scipy)",
    );
    close(tn_var, 0.5197625392115339, 1e-14, "truncnorm var (scipy)");
    let (lo, md, hi) = (1.0f64, 2.0f64, 5.0f64);
    let tri_var = (lo * lo + md * md + hi * hi - lo * md - lo * hi - md * hi) / 18.0;
    let lu_mean = (100.0 - 0.01) / (100.0f64 / 0.01).ln();
    let lu_m2 = (100.0f64.powi(2) - 0.01f64.powi(2)) / (2.0 * (100.0f64 / 0.01).ln());
    let ln_mean = 2.0 * (0.125f64).exp();
    let ln_var = (0.25f64.exp() - 1.0) * 4.0 * 0.25f64.exp();
    let expected: Vec<(&str, f64, f64)> = vec![
        ("uniform", 0.5, 25.0f64 / 12.0),
        ("loguniform", lu_mean, lu_m2 - lu_mean * lu_mean),
        ("normal", 0.07, 1e-4),
        ("normal cut", tn_mean, tn_var),
        ("lognormal", ln_mean, ln_var),
        ("triangular", (lo + md + hi) / 3.0, tri_var),
        ("triangular mode at low", 1.0 / 3.0, 1.0 / 18.0),
    ];
    let all = cases();
    for (name, mean, var) in expected {
        let m = all.iter().find(|(n, _)| *n == name).unwrap().1;
        let x: Vec<f64> = u.iter().map(|&u| m.quantile(u)).collect();
        let n = x.len() as f64;
        let got_mean = x.iter().sum::<f64>() / n;
        let got_var = x.iter().map(|v| (v - got_mean).powi(2)).sum::<f64>() / n;
        let sd = var.sqrt();
        assert!(
            (got_mean - mean).abs() < 1e-3 * sd,
            "{name}: mean {got_mean}, want {mean} (error {:.2e} sd)",
            (got_mean - mean).abs() / sd
        );
        assert!(
            (got_var.sqrt() - sd).abs() < 1e-3 * sd,
            "{name}: sd {}, want {sd}",
            got_var.sqrt()
        );
    }
}

fn message(dist: Distribution, range: Option<(f64, f64)>, domain: Domain) -> String {
    match Marginal::new("object.mass", dist, range, domain) {
        Err(e @ SensitivityError::Config { .. }) => e.to_string(),
        other => panic!("{dist:?} {range:?}: expected an error, got {other:?}"),
    }
}

#[test]
fn bad_parameters_are_named() {
    let pos = Domain::Positive;
    let real = Domain::Real;
    let cases: Vec<(String, &[&str])> = vec![
        (
            message(Normal { mean: 1.0, sd: 0.0 }, None, real),
            &["object.mass: sd = 0", "> 0"],
        ),
        (
            message(
                Normal {
                    mean: 1.0,
                    sd: -2.0,
                },
                None,
                real,
            ),
            &["object.mass: sd = -2"],
        ),
        (
            message(
                LogNormal {
                    median: 1.0,
                    sigma: 0.0,
                },
                None,
                real,
            ),
            &["object.mass: sigma = 0"],
        ),
        (
            message(
                LogNormal {
                    median: -1.0,
                    sigma: 1.0,
                },
                None,
                real,
            ),
            &["object.mass: median = -1"],
        ),
        (
            message(
                Triangular {
                    low: 0.0,
                    mode: 1.5,
                    high: 1.0,
                },
                None,
                real,
            ),
            &["object.mass: mode = 1.5", "[0, 1]"],
        ),
        (
            message(
                Uniform {
                    low: 2.0,
                    high: 1.0,
                },
                None,
                real,
            ),
            &["object.mass: range = [2, 1]", "below"],
        ),
        (
            message(
                LogUniform {
                    low: 0.0,
                    high: 1.0,
                },
                None,
                real,
            ),
            &["object.mass: low = 0"],
        ),
        (
            message(Normal { mean: 1.0, sd: 1.0 }, Some((3.0, 3.0)), real),
            &["object.mass: range = [3, 3]"],
        ),
        (
            message(
                Normal {
                    mean: f64::NAN,
                    sd: 1.0,
                },
                None,
                real,
            ),
            &["object.mass: mean = NaN", "finite"],
        ),
        (
            message(Normal { mean: 0.0, sd: 1.0 }, Some((40.0, 41.0)), real),
            &["object.mass: range = [40, 41]", "no probability"],
        ),
        (
            message(
                Uniform {
                    low: 0.0,
                    high: 1.0,
                },
                Some((2.0, 3.0)),
                real,
            ),
            &["object.mass: range = [2, 3]", "no probability"],
        ),
        // The quantity must be positive.
        (
            message(
                Normal {
                    mean: 0.1,
                    sd: 0.01,
                },
                None,
                pos,
            ),
            &["object.mass: dist = normal", "unbounded below", "positive"],
        ),
        (
            message(
                Normal {
                    mean: 0.1,
                    sd: 0.01,
                },
                Some((0.0, 1.0)),
                pos,
            ),
            &["object.mass: range = [0, 1]", "reaches down to 0"],
        ),
        (
            message(
                Uniform {
                    low: -1.0,
                    high: 1.0,
                },
                None,
                pos,
            ),
            &["object.mass: dist = uniform", "-1", "positive"],
        ),
        (
            message(
                Triangular {
                    low: 0.0,
                    mode: 0.5,
                    high: 1.0,
                },
                None,
                pos,
            ),
            &["object.mass: dist = triangular"],
        ),
    ];
    for (msg, parts) in cases {
        for p in parts {
            assert!(msg.contains(p), "{msg:?} lacks {p:?}");
        }
    }
    // Allowed where the quantity must be positive.
    for (dist, range) in [
        (
            LogNormal {
                median: 1.0,
                sigma: 2.0,
            },
            None,
        ),
        (
            LogUniform {
                low: 1e-3,
                high: 1.0,
            },
            None,
        ),
        (
            Normal {
                mean: 0.1,
                sd: 0.05,
            },
            Some((0.01, 1.0)),
        ),
        (
            Uniform {
                low: -1.0,
                high: 1.0,
            },
            Some((0.5, 1.0)),
        ),
    ] {
        let m = Marginal::new("object.mass", dist, range, pos).unwrap();
        assert!(m.quantile(0.0) > 0.0);
    }
}
