//! A lightly damped, weakly nonlinear oscillator in closed form (averaging method).
//!
//! `m u'' + C u' + Q u'|u'| + K1 u + K2 u^2 + K3 u^3 = 0`
//!
//! For small amplitudes (`|K2| a << K1`, damping ratio well below 1) the method of averaging
//! (Krylov–Bogoliubov, with Lindstedt's frequency correction; Nayfeh & Mook, *Nonlinear
//! Oscillations*, ch. 2–4) gives `u = a cos psi` plus a second harmonic and a mean shift, with
//!
//! - amplitude: `a' = -lambda a - mu a^2`, `lambda = C / 2m`, `mu = 4 Q w0 / (3 pi m)`
//!   (a Bernoulli equation: closed form);
//! - phase: `psi' = w_d - mu a tan theta + nu a^2`, `w_d = w0 sqrt(1 - zeta^2)`,
//!   `tan theta = lambda / w_d`,
//!   `nu = 3 alpha3 / (8 w0) - 5 alpha2^2 / (12 w0^3)`, `alpha_k = K_k / m`;
//! - shape: `u = a cos psi + (h2 a^2 / 6) cos 2 psi - h2 a^2 / 2`, `h2 = alpha2 / w0^2`, with
//!   the first-order ripple of amplitude and phase that the quadratic damping drives within a
//!   cycle (its 2nd and 4th harmonics).
//!
//! Against DOPRI5 at rtol 1e-12 on the paper's tool ringing on its stop, from an amplitude of
//! 0.1 of the stop's preload depth, its error stays below 5e-4 of the initial amplitude over 12
//! periods and shrinks with the amplitude (tests below); `ringing_tail.rs` uses it only there.

use std::f64::consts::PI;

/// The coefficients of the oscillator's equation (SI: kg, N s/m, N s^2/m^2, N/m, N/m^2, N/m^3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coefficients {
    pub m: f64,
    pub c: f64,
    pub q: f64,
    pub k1: f64,
    pub k2: f64,
    pub k3: f64,
}

impl Coefficients {
    /// Undamped angular frequency of the linear part, `sqrt(k1 / m)` (rad/s).
    pub fn w0(&self) -> f64 {
        (self.k1 / self.m).sqrt()
    }

    /// Amplitude decay rate of the linear damping, `c / 2m` (1/s).
    pub fn linear_decay(&self) -> f64 {
        self.c / (2.0 * self.m)
    }

    /// Amplitude decay rate per metre of amplitude of the quadratic (orifice) damping,
    /// averaged over a cycle, `4 q w0 / (3 pi m)` (1/(m s)): `a' = -(lambda + mu a) a`.
    pub fn orifice_decay(&self) -> f64 {
        4.0 * self.q * self.w0() / (3.0 * PI * self.m)
    }
}

/// One oscillation from `t0`: amplitude and phase laws and their initial values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ringing {
    pub t0: f64,
    /// Undamped angular frequency (rad/s) and damping ratio of the linear part.
    pub w0: f64,
    pub zeta: f64,
    wd: f64,
    /// `atan2(lambda, w_d)`: the ripple's phase offset (rad), and `sin 2 theta`, `cos 2 theta`.
    theta: f64,
    sin_cos_2theta: (f64, f64),
    lambda: f64,
    mu: f64,
    nu: f64,
    h2: f64,
    /// `Q / m` (1/m): the odd harmonics the orifice's quadratic damping drives.
    q_m: f64,
    /// Amplitude (m) and phase (rad) at `t0`.
    pub a0: f64,
    psi0: f64,
}

impl Ringing {
    /// The oscillation through `u(t0) = u0`, `u'(t0) = v0`; `None` unless the linear part is a
    /// spring (`K1 > 0`) with damping ratio in `[0, 0.5)` and `Q >= 0`.
    pub fn through(c: &Coefficients, t0: f64, u0: f64, v0: f64) -> Option<Ringing> {
        let ok = |x: f64| x.is_finite();
        if !(c.m > 0.0 && c.k1 > 0.0 && c.c >= 0.0 && c.q >= 0.0)
            || ![c.k2, c.k3, u0, v0].iter().all(|x| ok(*x))
        {
            return None;
        }
        let w0 = c.w0();
        let lambda = c.linear_decay();
        let zeta = lambda / w0;
        if zeta >= 0.5 {
            return None;
        }
        let (alpha2, alpha3) = (c.k2 / c.m, c.k3 / c.m);
        let mut r = Ringing {
            t0,
            w0,
            zeta,
            wd: w0 * (1.0 - zeta * zeta).sqrt(),
            theta: 0.0,
            sin_cos_2theta: (0.0, 1.0),
            lambda,
            mu: c.orifice_decay(),
            nu: 3.0 * alpha3 / (8.0 * w0) - 5.0 * alpha2 * alpha2 / (12.0 * w0.powi(3)),
            h2: alpha2 / (w0 * w0),
            q_m: c.q / c.m,
            a0: 0.0,
            psi0: 0.0,
        };
        r.theta = r.lambda.atan2(r.wd);
        r.sin_cos_2theta = (2.0 * r.theta).sin_cos();
        // Amplitude and phase from the state: the linear oscillator's values, then Newton on
        // `state(t0) = (u0, v0)` (the harmonic and mean terms are of order h2 a^2).
        let a_lin = u0.hypot((v0 + r.lambda * u0) / r.wd);
        let (mut a, mut psi) = (a_lin, (-(v0 + r.lambda * u0) / r.wd).atan2(u0));
        let mut converged = a_lin == 0.0;
        for _ in 0..12 {
            let f = |a: f64, psi: f64| {
                let (u, v) = r.shape(a, psi);
                (u - u0, (v - v0) / r.wd)
            };
            let (f0, g0) = f(a, psi);
            if f0.abs().max(g0.abs()) <= 1e-13 * a_lin {
                converged = true;
                break;
            }
            let da = 1e-7 * a;
            let dp = 1e-7;
            let (fa, ga) = f(a + da, psi);
            let (fp, gp) = f(a, psi + dp);
            let (j11, j21, j12, j22) = (
                (fa - f0) / da,
                (ga - g0) / da,
                (fp - f0) / dp,
                (gp - g0) / dp,
            );
            let det = j11 * j22 - j12 * j21;
            if !(det.abs() > 0.0) {
                break;
            }
            a -= (f0 * j22 - g0 * j12) / det;
            psi -= (j11 * g0 - j21 * f0) / det;
        }
        // a state too far from the small-amplitude regime has no (or a spurious) fit
        if !converged || !((a - a_lin).abs() <= 0.25 * a_lin) {
            return None;
        }
        r.a0 = a;
        r.psi0 = psi;
        Some(r)
    }

    /// Linear decay rate of the amplitude, `lambda = C / 2m` (1/s).
    pub fn decay_rate(&self) -> f64 {
        self.lambda
    }

    /// The largest rate at which the amplitude can decay from `t0` on (1/s): `lambda + mu a0`,
    /// linear and orifice damping, whose share falls with the amplitude.
    pub fn fastest_decay_rate(&self) -> f64 {
        self.lambda + self.mu * self.a0
    }

    /// Equivalent damping ratio of the quadratic damping at the initial amplitude, `mu a0 / w0`.
    pub fn orifice_damping_ratio(&self) -> f64 {
        self.mu * self.a0 / self.w0
    }

    /// Energy of the linear oscillation of amplitude `a` (m) for a mass `m` (kg):
    /// `m (w0 a)^2 / 2` (J).
    pub fn energy(&self, m: f64, a: f64) -> f64 {
        0.5 * m * (self.w0 * a).powi(2)
    }

    /// Amplitude at `t` (m).
    pub fn amplitude(&self, t: f64) -> f64 {
        let tau = (t - self.t0).max(0.0);
        let e = (-self.lambda * tau).exp();
        if self.mu * self.a0 == 0.0 {
            return self.a0 * e;
        }
        if self.lambda == 0.0 {
            return self.a0 / (1.0 + self.mu * self.a0 * tau);
        }
        self.lambda * self.a0 * e / (self.lambda + self.mu * self.a0 * (1.0 - e))
    }

    /// Phase rate at amplitude `a` (rad/s): the damped frequency, the orifice's shift
    /// `-mu a tan theta` (`tan theta = lambda / w_d`), Lindstedt's `nu a^2`.
    fn phase_rate(&self, a: f64) -> f64 {
        self.wd - self.mu * a * self.lambda / self.wd + self.nu * a * a
    }

    /// Phase at `t` (rad): `psi0 + int_0^tau phase_rate(a)`
    /// `= psi0 + w_d tau - (mu lambda / w_d) int a + nu int a^2`, both integrals of the
    /// Bernoulli amplitude in closed form.
    fn phase(&self, t: f64) -> f64 {
        let tau = (t - self.t0).max(0.0);
        if self.mu == 0.0 && self.nu == 0.0 {
            return self.psi0 + self.wd * tau;
        }
        let (int_a, int_a2) = self.amplitude_integrals(tau);
        self.psi0 + self.wd * tau - self.mu * self.lambda / self.wd * int_a + self.nu * int_a2
    }

    /// `int_0^tau a` and `int_0^tau a^2` for `a' = -lambda a - mu a^2`: with
    /// `E = exp(-lambda tau)`, `b = mu a0 / lambda`, `x = b (1 - E)`:
    /// `int a = ln(1 + x) / mu`, `int a^2 = a0^2 / (lambda b^2) ((1 + b) x / (1 + x) - ln(1 + x))`
    /// (by series for small `x`, where the difference cancels).
    pub(crate) fn amplitude_integrals(&self, tau: f64) -> (f64, f64) {
        let (a0, l, m) = (self.a0, self.lambda, self.mu);
        if l == 0.0 {
            // a = a0 / (1 + mu a0 tau)
            let y = m * a0 * tau;
            return if y == 0.0 {
                (a0 * tau, a0 * a0 * tau)
            } else {
                (y.ln_1p() / m, a0 * a0 * tau / (1.0 + y))
            };
        }
        let one_minus_e = -(-l * tau).exp_m1();
        let b = m * a0 / l;
        let x = b * one_minus_e;
        if x < 1e-3 {
            // series in x = b d, d = 1 - E: ln(1+x)/x = sum (-x)^n/(n+1), and
            // f/b^2 = sum_{n>=1} (-1)^(n+1) (b^(n-1) + ((n-1)/n) b^(n-2)) d^n
            let d = one_minus_e;
            let (mut int_a, mut f_over_b2) = (0.0, d);
            let (mut xn, mut bd) = (1.0, d); // x^n, and b^(n-2) d^n from n = 2
            for n in 0..10 {
                let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                int_a += sign * xn / (n + 1) as f64;
                xn *= x;
            }
            for n in 2..10 {
                let nf = n as f64;
                bd *= if n == 2 { d } else { b * d };
                let sign = if n % 2 == 1 { 1.0 } else { -1.0 };
                f_over_b2 += sign * (b * bd + (nf - 1.0) / nf * bd);
            }
            return (a0 / l * d * int_a, a0 * a0 / l * f_over_b2);
        }
        let ln = x.ln_1p();
        (
            (ln / m),
            a0 * a0 / (l * b * b) * ((1.0 + b) * x / (1.0 + x) - ln),
        )
    }

    /// Displacement `u` (m) and velocity `u'` (m/s) at `t >= t0`.
    pub fn state(&self, t: f64) -> (f64, f64) {
        self.shape(self.amplitude(t), self.phase(t))
    }

    /// `u` and `u'` for mean amplitude `a` and mean phase `psi`, in the damped oscillator's own
    /// frame (`u = A cos P`, `u' = -A (w_d sin P + lambda cos P)`, exact for the linear part),
    /// where `A`, `P` carry the first-order ripple the quadratic damping drives within a cycle,
    /// plus the second harmonic and mean shift of the quadratic stiffness.
    fn shape(&self, a: f64, psi: f64) -> (f64, f64) {
        // ripple of amplitude and phase (variation of parameters, averaged to first order)
        // the harmonics by double and difference angles: two sin_cos per call, not four, in
        // the tail's hottest function (its ledger quadrature calls it at every node)
        let x = psi + self.theta;
        let (s2x, c2x) = (2.0 * x).sin_cos();
        let (s4x, c4x) = (2.0 * s2x * c2x, (c2x - s2x) * (c2x + s2x));
        let tan = self.lambda / self.wd;
        let r = self.q_m * self.w0 / self.wd;
        let ripple_a = r
            * a
            * a
            * ((4.0 / 5.0) * s2x
                - (2.0 / 35.0) * s4x
                - tan * ((8.0 / 15.0) * c2x - (8.0 / 105.0) * c4x))
            / PI;
        let ripple_psi = r
            * a
            * ((8.0 / 15.0) * c2x - (8.0 / 105.0) * c4x
                + tan * ((4.0 / 5.0) * s2x - (2.0 / 35.0) * s4x))
            / PI;
        let (aa, pp) = (a + ripple_a, psi + ripple_psi);
        let (s1, c1) = pp.sin_cos();
        // second harmonic and mean shift of the quadratic stiffness (Lindstedt)
        let rate = self.phase_rate(a);
        let da = -(self.lambda + self.mu * a) * a;
        // 2 psi = 2 x - 2 theta
        let (st, ct) = self.sin_cos_2theta;
        let (s2, c2) = (s2x * ct - c2x * st, c2x * ct + s2x * st);
        let harmonic = self.h2 * (c2 / 6.0 - 0.5);
        let u = aa * c1 + a * a * harmonic;
        let v = -aa * ((self.wd + self.nu * a * a) * s1 + self.lambda * c1)
            + 2.0 * a * da * harmonic
            - self.h2 * a * a / 3.0 * rate * s2;
        (u, v)
    }

    /// A bound of `|u|` from `t0` on (m): the amplitude never grows.
    pub fn reach(&self) -> f64 {
        self.a0 + 2.0 / 3.0 * self.h2.abs() * self.a0 * self.a0
    }

    /// A bound of `|u'|` from `t0` on (m/s).
    pub fn speed_bound(&self) -> f64 {
        1.1 * (self.w0 + self.lambda + self.mu * self.a0) * self.reach()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cushion_ode::{solve, OdeSystem, SolverOptions, State, Tolerance};

    struct Osc(Coefficients);
    impl OdeSystem<2> for Osc {
        fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
            let c = &self.0;
            let (u, v) = (y[0], y[1]);
            let f = c.c * v + c.q * v * v.abs() + c.k1 * u + c.k2 * u * u + c.k3 * u * u * u;
            State::<2>::new(v, -f / c.m)
        }
    }

    fn reference(c: &Coefficients, u0: f64, v0: f64, t: f64) -> (f64, f64) {
        let opts = SolverOptions {
            rtol: Tolerance::Scalar(1e-12),
            atol: Tolerance::Scalar(1e-18),
            ..SolverOptions::default()
        };
        let sol = solve(&mut Osc(*c), 0.0, State::<2>::new(u0, v0), t, &opts);
        (sol.y[0], sol.y[1])
    }

    /// The tool of the paper scene on its forward stop: Hertz stop (k_e, chi_e at the preload
    /// depth 0.164 mm), viscous friction, orifice.
    fn paper_like() -> (Coefficients, f64) {
        let (k, chi, depth): (f64, f64, f64) = (0.6e6, 1.35e6, 1.64e-4);
        let c = Coefficients {
            m: 0.048,
            c: chi * depth * depth.sqrt() + 0.5,
            q: 66.0,
            k1: 1.5 * k * depth.sqrt(),
            k2: -0.375 * k / depth.sqrt(),
            k3: -0.0625 * k / (depth * depth.sqrt()),
        };
        (c, depth)
    }

    #[test]
    fn linear_damped_oscillator_is_exact() {
        let c = Coefficients {
            m: 2.0,
            c: 0.3,
            q: 0.0,
            k1: 50.0,
            k2: 0.0,
            k3: 0.0,
        };
        let r = Ringing::through(&c, 0.0, 0.01, -0.2).unwrap();
        let (w0, lambda): (f64, f64) = (5.0, 0.075);
        let wd = (w0 * w0 - lambda * lambda).sqrt();
        // closed form of the linear oscillator
        let (a, b) = (0.01, (-0.2 + lambda * 0.01) / wd);
        for t in [0.0, 0.3, 1.7, 6.0] {
            let e = (-lambda * t).exp();
            let u = e * (a * (wd * t).cos() + b * (wd * t).sin());
            let v = -lambda * u + e * wd * (-a * (wd * t).sin() + b * (wd * t).cos());
            let (ur, vr) = r.state(t);
            assert!(
                (ur - u).abs() < 1e-15 && (vr - v).abs() < 1e-14,
                "t={t}: {ur} {u}, {vr} {v}"
            );
        }
    }

    #[test]
    fn matches_the_integrated_oscillator_with_error_of_second_order() {
        // Ring down from amplitudes eps * depth for 0.15 s (~12 periods, ~5 time constants);
        // compare with DOPRI5 at rtol 1e-12. The error relative to the initial amplitude shrinks
        // with eps (within a cycle to first order: 4.6e-4 at eps = 0.1; the slow drift of
        // amplitude and phase to second order, 1.7e-4 at whole periods).
        let (c, depth) = paper_like();
        let mut errs = Vec::new();
        for eps in [0.2, 0.1, 0.05] {
            let (u0, v0) = (0.3 * eps * depth, -0.95 * eps * depth * 490.0);
            let r = Ringing::through(&c, 0.0, u0, v0).unwrap();
            let mut worst: f64 = 0.0;
            for t in [0.0, 0.002, 0.013, 0.05, 0.1, 0.15] {
                let (u, v) = r.state(t);
                let (ur, vr) = reference(&c, u0, v0, t);
                let e = ((u - ur).abs() / r.a0).max((v - vr).abs() / (r.a0 * r.w0));
                worst = worst.max(e);
            }
            errs.push(worst);
        }
        assert!(errs[1] < 6e-4, "{errs:?}");
        assert!(
            errs[0] / errs[1] > 1.8 && errs[1] / errs[2] > 1.8,
            "{errs:?}"
        );
    }

    #[test]
    fn amplitude_law_solves_its_bernoulli_equation() {
        let (c, depth) = paper_like();
        let r = Ringing::through(&c, 0.0, 0.1 * depth, 0.0).unwrap();
        let (lambda, mu) = (r.lambda, r.mu);
        for t in [0.01, 0.05, 0.2] {
            let h = 1e-6;
            let da = (r.amplitude(t + h) - r.amplitude(t - h)) / (2.0 * h);
            let a = r.amplitude(t);
            assert!(
                (da + lambda * a + mu * a * a).abs() < 1e-9 * a * lambda,
                "t={t}"
            );
        }
    }

    #[test]
    fn amplitude_integrals_match_quadrature() {
        // closed forms (and their series for small orifice damping) against Simpson's rule
        let (c, depth) = paper_like();
        for (q, eps) in [(66.0, 0.1), (66.0, 1e-5), (0.0, 0.1), (3000.0, 0.02)] {
            let r = Ringing::through(&Coefficients { q, ..c }, 0.0, eps * depth, 0.0).unwrap();
            for tau in [1e-4, 0.01, 0.2] {
                let n = 20000;
                let h = tau / n as f64;
                let (mut i1, mut i2) = (0.0, 0.0);
                for k in 0..=n {
                    let w = if k == 0 || k == n {
                        1.0
                    } else if k % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    let a = r.amplitude(k as f64 * h);
                    i1 += w * a * h / 3.0;
                    i2 += w * a * a * h / 3.0;
                }
                let (c1, c2) = r.amplitude_integrals(tau);
                assert!(
                    (c1 - i1).abs() <= 1e-10 * i1 && (c2 - i2).abs() <= 1e-10 * i2,
                    "q={q} eps={eps} tau={tau}: {c1} {i1} {c2} {i2}"
                );
            }
        }
    }

    #[test]
    fn refuses_what_it_cannot_describe() {
        let base = Coefficients {
            m: 1.0,
            c: 0.1,
            q: 0.0,
            k1: 1.0,
            k2: 0.0,
            k3: 0.0,
        };
        assert!(Ringing::through(&Coefficients { k1: -1.0, ..base }, 0.0, 0.1, 0.0).is_none());
        assert!(Ringing::through(&Coefficients { c: 1.2, ..base }, 0.0, 0.1, 0.0).is_none());
        assert!(Ringing::through(&base, 0.0, f64::NAN, 0.0).is_none());
    }
}
