//! The gas law of the right-hand side, `p1(s) = p10 (V_g0 / (V_g0 - A s))^kappa` (Pa; `s` in m,
//! `A` in m^2, volumes in m^3), evaluated near the stroke of its last exact evaluation by a
//! power series instead of `ln` and `exp`.
//!
//! A step's stages lie close together, so each evaluation is near the last one. With `s_n` the
//! stroke of the last exact evaluation, `p_n = p1(s_n)`, `V_n = V_g0 - A s_n` and
//! `u = A (s - s_n) / V_n`: `p1(s) = p_n (1 - u)^(-kappa) = p_n sum_k c_k u^k`, with
//! `c_0 = 1`, `c_k = c_(k-1) (kappa + k - 1) / k` (binomial series). For `|u| <= U_MAX`
//! the terms left out weigh less than 1e-18 of the sum for every allowed `kappa` (1 to 2);
//! farther out the law is evaluated exactly and `s_n` moves there. The value then differs from
//! `powf` by at most about 9 units in the last place (the exact law: 2.4), and the
//! right-hand side spends about 40 instructions on the gas instead of about 105 (`ln`, `exp`),
//! in a chain of five dependent multiply-adds (Estrin's scheme, below).
//! The anchor depends on the evaluations before, so a value may differ in its last bits from
//! one run's history to another's; a run is still reproducible to the bit.
use std::cell::Cell;

/// Largest `|u|` for the series (a stroke change of `V_n / 32 / A`: 1.9 mm in the paper's
/// module).
const U_MAX: f64 = 1.0 / 32.0;
/// Highest power of the series.
const TERMS: usize = 12;

/// The last exact evaluation: stroke (m), pressure (Pa) and `A / V` there (1/m).
#[derive(Clone, Copy, Debug)]
struct Anchor {
    s: f64,
    p: f64,
    a_over_v: f64,
}

/// The adiabatic (or polytropic) gas law of one module, with its anchor.
#[derive(Clone, Debug)]
pub struct GasLaw {
    p10: f64,
    v_g0: f64,
    area: f64,
    kappa: f64,
    coef: [f64; TERMS + 1],
    anchor: Cell<Anchor>,
}

impl GasLaw {
    /// `p10` (Pa) at `s = 0`, gas volume `v_g0` (m^3) there, `area` (m^2) by which the volume
    /// shrinks per metre of `s`, exponent `kappa` in [1, 2].
    pub fn new(p10: f64, v_g0: f64, area: f64, kappa: f64) -> GasLaw {
        let mut coef = [1.0; TERMS + 1];
        for k in 1..=TERMS {
            coef[k] = coef[k - 1] * (kappa + k as f64 - 1.0) / k as f64;
        }
        GasLaw {
            p10,
            v_g0,
            area,
            kappa,
            coef,
            anchor: Cell::new(Anchor {
                s: 0.0,
                p: p10,
                a_over_v: area / v_g0,
            }),
        }
    }

    /// The exact law, `exp(kappa ln(V_g0 / V))` (see `physics::gas_pressure`).
    pub fn exact(&self, s: f64) -> f64 {
        crate::physics::gas_pressure(self.p10, self.v_g0, self.area, self.kappa, s)
    }

    /// `dp1/ds` at `s`, where the pressure is `p` (Pa/m): `kappa p area / (V_g0 - area s)`.
    pub fn slope(&self, s: f64, p: f64) -> f64 {
        self.kappa * p * self.area / (self.v_g0 - self.area * s)
    }

    /// `p1(s)` (Pa): the series about the anchor when `s` is near it, else the exact law (and
    /// the anchor moves to `s`).
    #[inline]
    pub fn pressure(&self, s: f64) -> f64 {
        let a = self.anchor.get();
        let u = a.a_over_v * (s - a.s);
        if u.abs() <= U_MAX {
            // Estrin's scheme: powers u^2, u^4, u^8 and pairs of terms, a chain of five dependent
            // multiply-adds where Horner's rule has twelve. The stages of a step wait on one
            // another's right-hand side, so the depth of this chain (its latency), not the count
            // of its operations, is what the run's time sees: a few more multiplications buy a
            // chain less than half as long (`bash lab/wall_time.sh` shows the effect). Its
            // accuracy is guarded by `tests::matches_pow_to_a_few_ulp`.
            let c = &self.coef;
            let u2 = u * u;
            let u4 = u2 * u2;
            let u8 = u4 * u4;
            let r0 = (c[0] + c[1] * u) + (c[2] + c[3] * u) * u2;
            let r1 = (c[4] + c[5] * u) + (c[6] + c[7] * u) * u2;
            let r2 = (c[8] + c[9] * u) + (c[10] + c[11] * u) * u2;
            let sum = (r0 + r1 * u4) + (r2 + c[12] * u4) * u8;
            a.p * sum
        } else {
            self.move_anchor(s)
        }
    }

    #[inline(never)]
    fn move_anchor(&self, s: f64) -> f64 {
        let p = self.exact(s);
        let v = self.v_g0 - self.area * s;
        // a volume at or below zero (outside any valid scene's stroke) keeps the old anchor
        if p.is_finite() && v > 0.0 {
            self.anchor.set(Anchor {
                s,
                p,
                a_over_v: self.area / v,
            });
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (f64::EPSILON * b.abs())
    }

    /// Against `powf` (glibc's pow, correctly rounded in practice) from s = -1 mm to 50 mm (the
    /// paper's stroke is 23 mm; at 50 mm the gas holds a fifth of its volume), for
    /// exponents across the allowed range, walking in small and large strides so that both the
    /// series and the re-anchoring are used.
    #[test]
    fn matches_pow_to_a_few_ulp() {
        let (p10, v_g0, a_p) = (1000.0, 7.63e-5, std::f64::consts::PI * 0.02 * 0.02);
        for &kappa in &[1.0, 1.0001, 1.4, 5.0 / 3.0, 2.0] {
            let law = GasLaw::new(p10, v_g0, a_p, kappa);
            let mut worst: f64 = 0.0;
            let mut worst_exact: f64 = 0.0;
            let mut anchored = 0;
            for &stride in &[1e-6, 3.7e-5, 4.1e-4, 2.9e-3] {
                let mut s = -1e-3;
                while s < 0.05 {
                    let before = law.anchor.get().s;
                    let p = law.pressure(s);
                    if law.anchor.get().s != before {
                        anchored += 1;
                    }
                    let exact = p10 * (v_g0 / (v_g0 - a_p * s)).powf(kappa);
                    worst = worst.max(ulps(p, exact));
                    worst_exact = worst_exact.max(ulps(law.exact(s), exact));
                    s += stride;
                }
            }
            // measured: 5.4 to 9.3 ulp (the exact law itself: 1.0 to 2.4), the largest where the
            // gas is compressed to a fifth of its volume
            assert!(worst <= 10.0, "kappa {kappa}: {worst} ulp");
            assert!(
                worst_exact <= 4.0,
                "kappa {kappa}: exact law {worst_exact} ulp"
            );
            assert!(
                anchored > 10,
                "kappa {kappa}: re-anchored only {anchored} times"
            );
        }
    }

    /// The series is used (not the exact law) for a point near the anchor, and gives the
    /// hand-computed value: `p1(s) = 1000 (V_g0 / (V_g0 - A s))^1.4` at `s` = 1 mm.
    #[test]
    fn series_near_the_anchor_gives_the_hand_value() {
        let a_p = std::f64::consts::PI * 0.02 * 0.02;
        let law = GasLaw::new(1000.0, 7.63e-5, a_p, 1.4);
        let s = 1e-3;
        // u = A s / V_g0 = 0.01647 < 1/32: the anchor (s = 0) stays
        let p = law.pressure(s);
        assert_eq!(law.anchor.get().s, 0.0);
        // V = 7.63e-5 - 1.2566e-6 = 7.5043e-5 m^3; (7.63e-5 / 7.5043e-5)^1.4 = 1.023522...
        let by_hand = 1000.0 * (7.63e-5f64 / (7.63e-5 - a_p * 1e-3)).powf(1.4);
        assert!((p - 1023.5).abs() < 0.1, "{p}");
        assert!(ulps(p, by_hand) <= 4.0);
    }
}
