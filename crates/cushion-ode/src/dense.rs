//! Dense output of one step: Hairer's continuous extension of DOPRI5 (order 4), that of RODAS
//! (order 3, [`DenseOutput::from_coefficients`]), that of DOP853 (order 7, three more
//! coefficients, [`DenseOutput::order7`]), or the cubic Hermite interpolant for methods
//! without their own. DOPRI5's and RODAS's are built from the stages already computed, with
//! no extra right-hand-side evaluations; DOP853's needs three (`dop853.rs`).

use crate::State;

/// `y(t0 + theta h) = r1 + theta (r2 + (1-theta) (r3 + theta (r4 + (1-theta) r5)))`.
/// With `r5 = 0` this is the cubic Hermite interpolant of `y0, y1, f0, f1`.
///
/// DOP853's form continues the nesting with `r6, r7, r8` (the code's `contd8`):
/// `r5` is replaced by `r5 + theta (r6 + (1-theta) (r7 + theta r8))`. It is a separate branch
/// of [`DenseOutput::eval`], so the form of DOPRI5 computes exactly what it did.
#[derive(Clone, Copy, Debug)]
pub struct DenseOutput<const N: usize> {
    pub t0: f64,
    pub h: f64,
    r1: State<N>,
    r2: State<N>,
    r3: State<N>,
    r4: State<N>,
    r5: State<N>,
    /// DOP853's `r6, r7, r8`; `None` for the other forms.
    high: Option<[State<N>; 3]>,
}

impl<const N: usize> DenseOutput<N> {
    /// From the step's ends, slopes and the extra term `r5 = h * sum d_i k_i` (zero for Hermite).
    pub fn new(
        t0: f64,
        h: f64,
        y0: &State<N>,
        y1: &State<N>,
        f0: &State<N>,
        f1: &State<N>,
        r5: State<N>,
    ) -> Self {
        let r2 = y1 - y0;
        let r3 = f0 * h - r2;
        let r4 = r2 - f1 * h - r3;
        DenseOutput {
            t0,
            h,
            r1: *y0,
            r2,
            r3,
            r4,
            r5,
            high: None,
        }
    }

    /// From the coefficients of the form above directly: a method's own continuous extension
    /// written in it (RODAS's: `r1 = y0`, `r2 = y1 - y0`, `r3`, `r4` from its stages,
    /// `r5 = 0`).
    pub fn from_coefficients(t0: f64, h: f64, [r1, r2, r3, r4, r5]: [State<N>; 5]) -> Self {
        DenseOutput {
            t0,
            h,
            r1,
            r2,
            r3,
            r4,
            r5,
            high: None,
        }
    }

    /// DOP853's continuous extension of order 7 from its eight coefficients (`r1 = y0`,
    /// `r2 = y1 - y0`, `r3 = h f0 - r2`, `r4 = r2 - h f1 - r3`, `r5..r8` from its stages).
    pub fn order7(t0: f64, h: f64, [r1, r2, r3, r4, r5, r6, r7, r8]: [State<N>; 8]) -> Self {
        DenseOutput {
            t0,
            h,
            r1,
            r2,
            r3,
            r4,
            r5,
            high: Some([r6, r7, r8]),
        }
    }

    /// The state at `t` (meant for `t` within the step; extrapolates outside it).
    #[inline]
    pub fn eval(&self, t: f64) -> State<N> {
        let theta = (t - self.t0) / self.h;
        let theta1 = 1.0 - theta;
        match &self.high {
            None => {
                self.r1
                    + (self.r2 + (self.r3 + (self.r4 + self.r5 * theta1) * theta) * theta1) * theta
            }
            Some([r6, r7, r8]) => {
                let r5 = self.r5 + (r6 + (r7 + r8 * theta) * theta1) * theta;
                self.r1 + (self.r2 + (self.r3 + (self.r4 + r5 * theta1) * theta) * theta1) * theta
            }
        }
    }

    /// A bound, per component, of how far the output strays from its chord (the straight line
    /// from `y(t0)` to `y(t0 + h)`) inside the step: the deviation is
    /// `theta (1-theta) (r3 + theta (r4 + (1-theta) r5))`, with `theta (1-theta) <= 1/4`.
    /// DOP853's adds `theta^2 (1-theta) r6`, `theta^2 (1-theta)^2 r7` and
    /// `theta^3 (1-theta)^2 r8` inside, whose factors are at most 4/27, 1/16 and 0.035.
    #[inline]
    pub fn chord_deviation(&self) -> State<N> {
        let inner = self.r3.abs() + self.r4.abs() + self.r5.abs() * 0.25;
        match &self.high {
            None => inner * 0.25,
            Some([r6, r7, r8]) => {
                (inner + r6.abs() * (4.0 / 27.0) + r7.abs() * 0.0625 + r8.abs() * 0.035) * 0.25
            }
        }
    }

    /// The dense output of the first `M` components (zeros beyond `N`): what an observer
    /// keeps of a step it may still search once the integrator has moved on. It evaluates to
    /// exactly those components of [`DenseOutput::eval`], whatever the method's form.
    pub fn leading<const M: usize>(&self) -> DenseOutput<M> {
        let mut out = DenseOutput::from_coefficients(0.0, 0.0, [State::<M>::zeros(); 5]);
        self.leading_into(&mut out);
        out
    }

    /// [`DenseOutput::leading`] written over `out`, in place: an observer that keeps the last
    /// step on every step overwrites its copy instead of moving a new one in.
    pub fn leading_into<const M: usize>(&self, out: &mut DenseOutput<M>) {
        fn cut<const N: usize, const M: usize>(s: &State<N>, o: &mut State<M>) {
            for i in 0..M {
                o[i] = if i < N { s[i] } else { 0.0 };
            }
        }
        out.t0 = self.t0;
        out.h = self.h;
        cut(&self.r1, &mut out.r1);
        cut(&self.r2, &mut out.r2);
        cut(&self.r3, &mut out.r3);
        cut(&self.r4, &mut out.r4);
        cut(&self.r5, &mut out.r5);
        match &self.high {
            None => out.high = None,
            Some(h) => {
                let o = out.high.get_or_insert([State::<M>::zeros(); 3]);
                for (a, b) in h.iter().zip(o) {
                    cut(a, b);
                }
            }
        }
    }

    /// End of the interval this output covers.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v3(a: f64, b: f64, c: f64) -> State<3> {
        State::<3>::new(a, b, c)
    }

    #[test]
    fn the_leading_components_evaluate_as_the_whole_output_does() {
        let r = [
            v3(1.0, -2.0, 3.0),
            v3(0.5, 0.25, -1.0),
            v3(-0.3, 0.7, 0.1),
            v3(0.2, -0.4, 0.9),
            v3(0.05, 0.3, -0.6),
            v3(0.11, -0.13, 0.17),
            v3(-0.19, 0.23, 0.29),
            v3(0.31, 0.37, -0.41),
        ];
        let order4 = DenseOutput::from_coefficients(0.5, 0.25, [r[0], r[1], r[2], r[3], r[4]]);
        let order7 = DenseOutput::order7(0.5, 0.25, r);
        // written in place over an output of the other form, as an observer keeping steps does
        let mut kept = [order7.leading::<5>(), order4.leading::<5>()];
        for (full, into) in [order4, order7].into_iter().zip(&mut kept) {
            let two: DenseOutput<2> = full.leading();
            let five: DenseOutput<5> = full.leading();
            full.leading_into(into);
            for t in [0.5, 0.55, 0.6125, 0.7, 0.75] {
                let (y, y2, y5) = (full.eval(t), two.eval(t), five.eval(t));
                assert_eq!(into.eval(t), y5, "in place, t = {t}");
                assert_eq!((y2[0], y2[1]), (y[0], y[1]));
                assert_eq!(
                    (y5[0], y5[1], y5[2], y5[3], y5[4]),
                    (y[0], y[1], y[2], 0.0, 0.0)
                );
            }
        }
        // the two forms differ inside the step (the test would not see a dropped `high`)
        assert!((order4.eval(0.6)[0] - order7.eval(0.6)[0]).abs() > 1e-4);
    }
}
