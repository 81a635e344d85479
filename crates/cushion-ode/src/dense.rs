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

    /// End of the interval this output covers.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }
}
