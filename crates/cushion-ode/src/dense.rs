//! Dense output of one step: Hairer's continuous extension of DOPRI5 (order 4), that of RODAS
//! (order 3, [`DenseOutput::from_coefficients`]), or the cubic Hermite interpolant for methods
//! without their own. Built from the stages already computed, no extra right-hand-side
//! evaluations.

use crate::State;

/// `y(t0 + theta h) = r1 + theta (r2 + (1-theta) (r3 + theta (r4 + (1-theta) r5)))`.
/// With `r5 = 0` this is the cubic Hermite interpolant of `y0, y1, f0, f1`.
#[derive(Clone, Copy, Debug)]
pub struct DenseOutput<const N: usize> {
    pub t0: f64,
    pub h: f64,
    r1: State<N>,
    r2: State<N>,
    r3: State<N>,
    r4: State<N>,
    r5: State<N>,
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
        }
    }

    /// The state at `t` (meant for `t` within the step; extrapolates outside it).
    #[inline]
    pub fn eval(&self, t: f64) -> State<N> {
        let theta = (t - self.t0) / self.h;
        let theta1 = 1.0 - theta;
        self.r1 + (self.r2 + (self.r3 + (self.r4 + self.r5 * theta1) * theta) * theta1) * theta
    }

    /// A bound, per component, of how far the output strays from its chord (the straight line
    /// from `y(t0)` to `y(t0 + h)`) inside the step: the deviation is
    /// `theta (1-theta) (r3 + theta (r4 + (1-theta) r5))`, with `theta (1-theta) <= 1/4`.
    #[inline]
    pub fn chord_deviation(&self) -> State<N> {
        (self.r3.abs() + self.r4.abs() + self.r5.abs() * 0.25) * 0.25
    }

    /// End of the interval this output covers.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }
}
