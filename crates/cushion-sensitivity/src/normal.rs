//! The standard normal distribution: its CDF `Φ` and its quantile `Φ⁻¹`, in double precision.
//!
//! - `Φ⁻¹`: Wichura's algorithm AS 241 (PPND16): M. J. Wichura, "Algorithm AS 241: The
//!   percentage points of the normal distribution", Applied Statistics 37(3), 477-484 (1988).
//!   Three rational approximations (the centre `|p - 1/2| <= 0.425`, then two tail regions in
//!   `r = sqrt(-ln min(p, 1-p))`), relative error about 1e-16 over `[1e-300, 1 - 1e-16]`; no
//!   refinement step is needed. The coefficients are those published (CPython's
//!   `statistics.NormalDist.inv_cdf` uses the same).
//! - `Φ(x) = erfc(-x/√2)/2`, `erfc` by the two expansions that CPython's `math.erfc` used before
//!   it called the C library: for `z < 1.5` the series `erf z = (2/√π) z e^{-z²} Σ (2z²)^n /
//!   (1·3···(2n+1))` (all terms positive, no cancellation), for `z >= 1.5` the continued fraction
//!   `erfc z = (z e^{-z²}/√π) / (z² + 1/2 - (1·1/2) / (z² + 5/2 - (2·3/2) / (z² + 9/2 - ...)))`
//!   (Abramowitz and Stegun 7.1.14 in its even form), 50 terms. Relative error below about
//!   5e-15 in both tails; the lower tail is exact in relative terms down to the subnormals, which
//!   is what truncation far in a tail needs.

/// `1/√π`.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;
const SERIES_CUTOFF: f64 = 1.5;
const SERIES_TERMS: usize = 25;
const CONTFRAC_TERMS: usize = 50;
/// `erfc z` underflows to 0 beyond (`erfc 27.3 < 2⁻¹⁰⁷⁴`).
const ERFC_ZERO_BEYOND: f64 = 27.3;

/// `erfc z` for `z >= 0` (the continued fraction or one minus the series).
fn erfc_nonnegative(z: f64) -> f64 {
    if z < SERIES_CUTOFF {
        return 1.0 - erf_series(z);
    }
    if z >= ERFC_ZERO_BEYOND {
        return 0.0;
    }
    let z2 = z * z;
    let mut a = 0.0;
    let mut da = 0.5;
    let (mut p, mut p_last) = (1.0, 0.0);
    let (mut q, mut q_last) = (da + z2, 1.0);
    for _ in 0..CONTFRAC_TERMS {
        a += da;
        da += 2.0;
        let b = da + z2;
        let t = p;
        p = b * p - a * p_last;
        p_last = t;
        let t = q;
        q = b * q - a * q_last;
        q_last = t;
    }
    p / q * z * (-z2).exp() * FRAC_1_SQRT_PI
}

/// `erf z` by its series, `|z| < 1.5`.
fn erf_series(z: f64) -> f64 {
    let z2 = z * z;
    let mut acc = 0.0;
    let mut fk = SERIES_TERMS as f64 + 0.5;
    for _ in 0..SERIES_TERMS {
        acc = 2.0 + z2 * acc / fk;
        fk -= 1.0;
    }
    acc * z * (-z2).exp() * FRAC_1_SQRT_PI
}

/// The complementary error function `erfc z = 1 - erf z`.
pub fn erfc(z: f64) -> f64 {
    if z.is_nan() {
        z
    } else if z >= 0.0 {
        erfc_nonnegative(z)
    } else {
        2.0 - erfc_nonnegative(-z)
    }
}

/// The standard normal CDF `Φ(x)`; `Φ(-∞) = 0`, `Φ(∞) = 1`.
pub fn cdf(x: f64) -> f64 {
    0.5 * erfc(-x * std::f64::consts::FRAC_1_SQRT_2)
}

/// The standard normal quantile `Φ⁻¹(p)` (AS 241); `-∞` at 0, `∞` at 1, NaN outside `[0, 1]`.
#[allow(clippy::excessive_precision)] // the coefficients as Wichura published them
pub fn quantile(p: f64) -> f64 {
    if !(0.0..=1.0).contains(&p) {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        let num = (((((((2.5090809287301226727e+3 * r + 3.3430575583588128105e+4) * r
            + 6.7265770927008700853e+4)
            * r
            + 4.5921953931549871457e+4)
            * r
            + 1.3731693765509461125e+4)
            * r
            + 1.9715909503065514427e+3)
            * r
            + 1.3314166789178437745e+2)
            * r
            + 3.3871328727963666080e+0)
            * q;
        let den = ((((((5.2264952788528545610e+3 * r + 2.8729085735721942674e+4) * r
            + 3.9307895800092710610e+4)
            * r
            + 2.1213794301586595867e+4)
            * r
            + 5.3941960214247511077e+3)
            * r
            + 6.8718700749205790830e+2)
            * r
            + 4.2313330701600911252e+1)
            * r
            + 1.0;
        return num / den;
    }
    let r = if q <= 0.0 { p } else { 1.0 - p };
    let r = (-r.ln()).sqrt();
    let x = if r <= 5.0 {
        let r = r - 1.6;
        let num = ((((((7.74545014278341407640e-4 * r + 2.27238449892691845833e-2) * r
            + 2.41780725177450611770e-1)
            * r
            + 1.27045825245236838258e+0)
            * r
            + 3.64784832476320460504e+0)
            * r
            + 5.76949722146069140550e+0)
            * r
            + 4.63033784615654529590e+0)
            * r
            + 1.42343711074968357734e+0;
        let den = ((((((1.05075007164441684324e-9 * r + 5.47593808499534494600e-4) * r
            + 1.51986665636164571966e-2)
            * r
            + 1.48103976427480074590e-1)
            * r
            + 6.89767334985100004550e-1)
            * r
            + 1.67638483018380384940e+0)
            * r
            + 2.05319162663775882187e+0)
            * r
            + 1.0;
        num / den
    } else {
        let r = r - 5.0;
        let num = ((((((2.01033439929228813265e-7 * r + 2.71155556874348757815e-5) * r
            + 1.24266094738807843860e-3)
            * r
            + 2.65321895265761230930e-2)
            * r
            + 2.96560571828504891230e-1)
            * r
            + 1.78482653991729133580e+0)
            * r
            + 5.46378491116411436990e+0)
            * r
            + 6.65790464350110377720e+0;
        let den = ((((((2.04426310338993978564e-15 * r + 1.42151175831644588870e-7) * r
            + 1.84631831751005468180e-5)
            * r
            + 7.86869131145613259100e-4)
            * r
            + 1.48753612908506148525e-2)
            * r
            + 1.36929880922735805310e-1)
            * r
            + 5.99832206555887937690e-1)
            * r
            + 1.0;
        num / den
    };
    if q < 0.0 {
        -x
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scipy.stats.norm.cdf(x)` (SciPy 1.17, Cephes `ndtr`).
    const CDF: [(f64, f64); 19] = [
        (-30.0, 4.906713927147908e-198),
        (-20.0, 2.7536241186061556e-89),
        (-10.0, 7.61985302416047e-24),
        (-8.0, 6.22096057427174e-16),
        (-5.0, 2.866515718791933e-07),
        (-3.0, 0.0013498980316300933),
        (-2.1, 0.017864420562816542),
        (-2.0, 0.022750131948179195),
        (-1.5, 0.06680720126885807),
        (-1.0, 0.15865525393145707),
        (-0.5, 0.3085375387259869),
        (-0.1, 0.460172162722971),
        (0.0, 0.5),
        (0.3, 0.6179114221889526),
        (1.0, 0.8413447460685429),
        (2.0, 0.9772498680518208),
        (3.0, 0.9986501019683699),
        (5.0, 0.9999997133484281),
        (8.0, 0.9999999999999993),
    ];

    /// `scipy.stats.norm.ppf(p)` (SciPy 1.17, Cephes `ndtri`).
    const QUANTILE: [(f64, f64); 17] = [
        (1e-300, -37.0470962993612),
        (1e-100, -21.273453560965322),
        (1e-20, -9.262340089798409),
        (1e-10, -6.361340902404056),
        (1e-05, -4.264890793922825),
        (0.001, -3.090232306167813),
        (0.025, -1.9599639845400545),
        (0.075, -1.4395314709384563),
        (0.1, -1.2815515655446004),
        (0.3, -0.5244005127080409),
        (0.5, 0.0),
        (0.7, 0.5244005127080407),
        (0.9, 1.2815515655446004),
        (0.925, 1.4395314709384563),
        (0.975, 1.959963984540054),
        (0.999, 3.090232306167813),
        (0.9999999999, 6.361340889697422),
    ];

    fn rel(a: f64, b: f64) -> f64 {
        if a == b {
            0.0
        } else {
            (a - b).abs() / b.abs()
        }
    }

    #[test]
    fn cdf_matches_scipy() {
        for (x, want) in CDF {
            let got = cdf(x);
            assert!(rel(got, want) < 5e-15, "Phi({x}) = {got:e}, scipy {want:e}");
        }
        assert_eq!(cdf(f64::NEG_INFINITY), 0.0);
        assert_eq!(cdf(f64::INFINITY), 1.0);
        assert!(cdf(f64::NAN).is_nan());
    }

    #[test]
    fn quantile_matches_scipy() {
        for (p, want) in QUANTILE {
            let got = quantile(p);
            assert!(
                rel(got, want) < 2e-15,
                "Phi^-1({p}) = {got:e}, scipy {want:e}"
            );
        }
        assert_eq!(quantile(0.0), f64::NEG_INFINITY);
        assert_eq!(quantile(1.0), f64::INFINITY);
        assert!(quantile(-0.1).is_nan() && quantile(1.1).is_nan() && quantile(f64::NAN).is_nan());
    }

    #[test]
    fn quantile_inverts_cdf() {
        // p over 30 decades in the lower tail and across the centre. A relative error δ in x
        // becomes about z² δ in p (the condition number of Φ at z is z φ(z)/Φ(z) ≈ z² in the
        // tail); Φ's own error is below 5e-15 (largest just inside the series' cutoff, where
        // erfc = 1 - erf loses digits).
        let mut worst: f64 = 0.0;
        let ps = (0..=3000)
            .map(|k| 10f64.powf(-30.0 + 30.0 * k as f64 / 3000.0) * 0.5)
            .chain((1..1000).map(|k| k as f64 / 1000.0));
        for p in ps {
            let z = quantile(p);
            worst = worst.max(rel(cdf(z), p) / (5e-15 + 1e-15 * z * z));
        }
        assert!(worst < 1.0, "round-trip error {worst} times the bound");
    }

    #[test]
    fn symmetric() {
        for k in 1..500 {
            let p = k as f64 / 1000.0;
            assert!((quantile(p) + quantile(1.0 - p)).abs() < 1e-15 * quantile(p).abs().max(1.0));
            let x = k as f64 / 50.0;
            assert!((cdf(x) + cdf(-x) - 1.0).abs() < 2e-16);
        }
    }
}
