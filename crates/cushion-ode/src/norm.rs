//! Hairer's error norm: RMS of `e_i / (atol_i + rtol_i * max(|y0_i|, |y1_i|))`, the mean taken
//! over the components that are not quadratures ([`crate::SolverOptions::quadratures`]).

use crate::State;

/// Tolerances resolved to one number per component.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Weights<const N: usize> {
    pub rtol: State<N>,
    pub atol: State<N>,
    /// What the sum of squares is averaged over: `N` less the quadratures (at least 1).
    pub averaged_over: f64,
}

impl<const N: usize> Weights<N> {
    /// The settings' tolerances, one number per component.
    pub fn of(opts: &crate::SolverOptions) -> Self {
        let mut rtol = State::<N>::zeros();
        let mut atol = State::<N>::zeros();
        for i in 0..N {
            rtol[i] = opts.rtol.get(i);
            atol[i] = opts.atol.get(i);
        }
        let averaged_over = N.saturating_sub(opts.quadratures).max(1) as f64;
        Weights {
            rtol,
            atol,
            averaged_over,
        }
    }

    /// The scale of each component at `y`: `atol + rtol |y|`.
    #[inline]
    pub fn scale(&self, y: &State<N>) -> State<N> {
        let mut sk = self.atol;
        for i in 0..N {
            sk[i] += self.rtol[i] * y[i].abs();
        }
        sk
    }

    /// RMS norm of `err` scaled by `atol + rtol * max(|y0|, |y1|)`.
    #[inline]
    pub fn error_norm(&self, err: &State<N>, y0: &State<N>, y1: &State<N>) -> f64 {
        let mut sum = 0.0;
        for i in 0..N {
            let sk = self.atol[i] + self.rtol[i] * y0[i].abs().max(y1[i].abs());
            let q = err[i] / sk;
            sum += q * q;
        }
        (sum / self.averaged_over).sqrt()
    }

    /// Hairer's DOP853 norm of its two estimates, `err5` (order 5) and `err3` (order 3), both
    /// `h` times the code's sums: with `E5`, `E3` the sums of squares of each scaled by
    /// `atol + rtol * max(|y0|, |y1|)`, `E5 / sqrt(n (E5 + 0.01 E3))` (the code's
    /// `|h| err sqrt(1 / (n deno))`, `deno = err + 0.01 err2`, whose sums lack the factor
    /// `h^2`); 0 when both vanish (the code's `deno = 1`).
    #[inline]
    pub fn dop853_error_norm(
        &self,
        err5: &State<N>,
        err3: &State<N>,
        y0: &State<N>,
        y1: &State<N>,
    ) -> f64 {
        let (mut e5, mut e3) = (0.0, 0.0);
        for i in 0..N {
            let sk = self.atol[i] + self.rtol[i] * y0[i].abs().max(y1[i].abs());
            let q5 = err5[i] / sk;
            let q3 = err3[i] / sk;
            e5 += q5 * q5;
            e3 += q3 * q3;
        }
        let deno = e5 + 0.01 * e3;
        if deno > 0.0 {
            e5 / (self.averaged_over * deno).sqrt()
        } else {
            0.0
        }
    }

    /// Sum of squares of `v / (atol + rtol * |y|)` (used by the initial step selection).
    #[inline]
    pub fn scaled_sq(&self, v: &State<N>, y: &State<N>) -> f64 {
        let mut sum = 0.0;
        for i in 0..N {
            let sk = self.atol[i] + self.rtol[i] * y[i].abs();
            let q = v[i] / sk;
            sum += q * q;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SolverOptions;

    fn weights(quadratures: usize) -> Weights<3> {
        Weights::of(&SolverOptions {
            rtol: 1e-3.into(),
            atol: 1e-6.into(),
            quadratures,
            ..SolverOptions::default()
        })
    }

    /// A quadrature adds its squared error to the sum but not to the count.
    #[test]
    fn quadratures_add_their_squares_but_not_to_the_count() {
        let y = State::<3>::new(1.0, -2.0, 1e3);
        let sk = [1e-6 + 1e-3, 1e-6 + 2e-3, 1e-6 + 1.0];
        let err = State::<3>::new(3e-3, -1e-3, 0.5);
        let q: Vec<f64> = (0..3).map(|i| err[i] / sk[i]).collect();
        let all = q.iter().map(|v| v * v).sum::<f64>();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b;
        assert!(close(
            weights(0).error_norm(&err, &y, &y),
            (all / 3.0).sqrt()
        ));
        assert!(close(
            weights(1).error_norm(&err, &y, &y),
            (all / 2.0).sqrt()
        ));
        // With an exact quadrature, the norm is the RMS over the other components.
        let exact = State::<3>::new(3e-3, -1e-3, 0.0);
        let others = q[0] * q[0] + q[1] * q[1];
        assert!(close(
            weights(1).error_norm(&exact, &y, &y),
            (others / 2.0).sqrt()
        ));
        // DOP853's norm averages over the same count.
        let e3 = State::<3>::new(1e-3, 0.0, 0.1);
        let (n0, n1) = (
            weights(0).dop853_error_norm(&err, &e3, &y, &y),
            weights(1).dop853_error_norm(&err, &e3, &y, &y),
        );
        assert!(close(n1, n0 * (3.0f64 / 2.0).sqrt()));
    }
}
