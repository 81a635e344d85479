//! Hairer's error norm: RMS of `e_i / (atol_i + rtol_i * max(|y0_i|, |y1_i|))`.

use crate::State;

/// Tolerances resolved to one number per component.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Weights<const N: usize> {
    pub rtol: State<N>,
    pub atol: State<N>,
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
        Weights { rtol, atol }
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
        (sum / N as f64).sqrt()
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
            e5 / (N as f64 * deno).sqrt()
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
