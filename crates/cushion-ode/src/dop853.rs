//! Hairer's DOP853 (Hairer, Nørsett & Wanner, *Solving ODEs I*, Sec. II.10; the Fortran code
//! DOP853): the explicit Runge–Kutta method of order 8 of Dormand and Prince with 12 stages,
//! its embedded error estimators of orders 5 and 3 combined as the code does, its continuous
//! extension of order 7 (three extra stages per accepted step), Hairer's PI controller with
//! the code's constants and his stiffness test.
//!
//! Evaluations, as the code counts them: 11 per attempt (stages 2..12; stage 1 is the last
//! step's `f(y1)`), and per accepted step one more for `f(y1)` and three for the dense output
//! ([`Stepper::complete`]), so 15 per accepted step and 11 per rejected one.
//!
//! Error estimate (the code's): with `sk = atol + rtol max(|y0|, |y1|)`,
//! `e5 = h sum er_i k_i` (order 5) and `e3 = h (sum b_i k_i - bhh1 k1 - bhh2 k9 - bhh3 k12)`
//! (order 3), `err = E5 / sqrt(n (E5 + 0.01 E3))` with `E5 = sum (e5/sk)^2`,
//! `E3 = sum (e3/sk)^2`: algebraically the code's `|h| err * sqrt(1 / (n deno))` with its
//! unscaled sums (`norm.rs`). The estimate behaves like `O(h^8)`.
//!
//! The coefficients are typed from the published digits (the code DOP853); the tests at the
//! bottom check every order condition up to order 8 (the 200 rooted trees), those of the
//! embedded estimators, the nodes, and compute the method's stability boundary.

mod coefficients;
#[cfg(test)]
mod tests;

use crate::controller::PiController;
use crate::dense::DenseOutput;
use crate::options::SolverOptions;
use crate::stepper::{Attempt, StepFailure, Stepper};
use crate::system::OdeSystem;
use crate::State;
use coefficients::*;

/// DOP853's stability boundary on the negative real axis: the `x` with `|R(-x)| = 1` for its
/// stability polynomial `R(z) = sum_j gamma_j z^j`, `gamma_j = 1/j!` up to `j = 8` and
/// `b^T A^(j-1) 1` for `j = 9..12` (computed in `tests::stability_boundary`).
pub const STABILITY_BOUNDARY: f64 = 6.393_651_522_851_909;

/// The loop's stiffness threshold on `h |lambda|` under DOP853: 0.9 of its stability boundary,
/// as [`crate::stiffness::THRESHOLD`] is of DOPRI5's (the code DOP853 itself tests 6.1).
pub const STIFFNESS_THRESHOLD: f64 = crate::stiffness::THRESHOLD_SHARE * STABILITY_BOUNDARY;

/// The `h |lambda|` past which an accepted DOP853 step that jumped is taken again
/// ([`crate::stepper::Stepper::stability_guard`]): its stability boundary. The combined
/// estimate `err5^2 / sqrt(err5^2 + 0.01 err3^2)` discounts `err5` by about `10 err5 / err3`,
/// and where a stiff mode makes `err3` large (a tool resting on its stop: 300 to 1,800 times
/// the tolerance) it passed a step 4.2 times the length of the one before, `h |lambda|` 6.9,
/// with `err5` at 25 times the tolerance (`cushion-model`,
/// `tests/model/peaks.rs::dop853_past_its_stability_boundary`).
pub const STABILITY_GUARD: f64 = STABILITY_BOUNDARY;

/// Where DOP853's continuous extension stops being stable on the negative real axis: for
/// `y' = lambda y`, `max |P(theta, z)|` over the step is 0.953 at `z = -5`, then 3.2 at `-5.5`
/// and 10.5 at `-6` (at `theta` about 0.83), while the step's own `|R(z)|` stays below 0.5.
/// A step held by stability (`h |lambda|` near 6.4) has a dense output that amplifies a fast
/// mode's deviation many times inside it
/// (`tests/integrator/dop853.rs::the_dense_output_is_stable_up_to_its_boundary_and_not_beyond`).
pub const DENSE_STABILITY_BOUNDARY: f64 = 5.0;

/// `y + h (a_1 k_1 + a_2 k_2 + ...)`, the sum in the code's order, component by component.
#[inline(always)]
fn stage_input<const N: usize, const M: usize>(
    y: &State<N>,
    h: f64,
    terms: [(f64, &State<N>); M],
) -> State<N> {
    y + weighted(terms) * h
}

/// `a_1 k_1 + a_2 k_2 + ...`.
#[inline(always)]
fn weighted<const N: usize, const M: usize>(terms: [(f64, &State<N>); M]) -> State<N> {
    let mut out = State::<N>::zeros();
    for n in 0..N {
        let mut acc = terms[0].1[n] * terms[0].0;
        for term in &terms[1..] {
            acc += term.1[n] * term.0;
        }
        out[n] = acc;
    }
    out
}

/// DOP853 with constant coefficients. Keeps the stages of the last attempt for its error
/// estimate, dense output and stiffness test.
pub struct Dop853<const N: usize> {
    /// `k[i]` is stage `i + 1`: `k[0] = f0`, `k[1..12]` stages 2..12 of the last attempt;
    /// once it is accepted, `k[12] = f(y1)` (stage 13) and `k[13..16]` the continuous
    /// extension's stages 14..16.
    k: [State<N>; 16],
    /// Input of stage 12 (at `t + h`), for the stiffness test.
    stage12_input: State<N>,
}

impl<const N: usize> Dop853<N> {
    pub fn new() -> Self {
        Dop853 {
            k: [State::<N>::zeros(); 16],
            stage12_input: State::<N>::zeros(),
        }
    }
}

impl<const N: usize> Default for Dop853<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Stepper<N> for Dop853<N> {
    type Controller = PiController;

    fn order(&self) -> u32 {
        8
    }

    fn is_adaptive(&self) -> bool {
        true
    }

    /// The code's controller: `beta = 0`, safety 0.9, `h_new / h` within `[1/3, 6]`
    /// (`fac1 = 0.333`, `fac2 = 6`), exponent `1/8 - 0.2 beta`. The settings' four
    /// controller numbers are DOPRI5's and do not apply.
    fn controller(&self, _opts: &SolverOptions) -> PiController {
        PiController::dop853()
    }

    fn stiffness_threshold(&self) -> f64 {
        STIFFNESS_THRESHOLD
    }

    fn dense_stability_boundary(&self) -> f64 {
        DENSE_STABILITY_BOUNDARY
    }

    fn stability_guard(&self) -> f64 {
        STABILITY_GUARD
    }

    /// Its steps are long and its error expects to fall like `h^8`: a kink inside one costs
    /// rejections (`kinks.rs`).
    fn lands_on_kinks(&self) -> bool {
        true
    }

    #[inline]
    fn step_into<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
        out: &mut Attempt<N>,
    ) -> Result<(), StepFailure> {
        let k = &mut self.k;
        k[0] = *f0;
        k[1] = sys.rhs(t + C2 * h, &stage_input(y, h, [(A21, &k[0])]));
        k[2] = sys.rhs(t + C3 * h, &stage_input(y, h, [(A31, &k[0]), (A32, &k[1])]));
        k[3] = sys.rhs(t + C4 * h, &stage_input(y, h, [(A41, &k[0]), (A43, &k[2])]));
        k[4] = sys.rhs(
            t + C5 * h,
            &stage_input(y, h, [(A51, &k[0]), (A53, &k[2]), (A54, &k[3])]),
        );
        k[5] = sys.rhs(
            t + C6 * h,
            &stage_input(y, h, [(A61, &k[0]), (A64, &k[3]), (A65, &k[4])]),
        );
        k[6] = sys.rhs(
            t + C7 * h,
            &stage_input(
                y,
                h,
                [(A71, &k[0]), (A74, &k[3]), (A75, &k[4]), (A76, &k[5])],
            ),
        );
        k[7] = sys.rhs(
            t + C8 * h,
            &stage_input(
                y,
                h,
                [
                    (A81, &k[0]),
                    (A84, &k[3]),
                    (A85, &k[4]),
                    (A86, &k[5]),
                    (A87, &k[6]),
                ],
            ),
        );
        k[8] = sys.rhs(
            t + C9 * h,
            &stage_input(
                y,
                h,
                [
                    (A91, &k[0]),
                    (A94, &k[3]),
                    (A95, &k[4]),
                    (A96, &k[5]),
                    (A97, &k[6]),
                    (A98, &k[7]),
                ],
            ),
        );
        k[9] = sys.rhs(
            t + C10 * h,
            &stage_input(
                y,
                h,
                [
                    (A101, &k[0]),
                    (A104, &k[3]),
                    (A105, &k[4]),
                    (A106, &k[5]),
                    (A107, &k[6]),
                    (A108, &k[7]),
                    (A109, &k[8]),
                ],
            ),
        );
        k[10] = sys.rhs(
            t + C11 * h,
            &stage_input(
                y,
                h,
                [
                    (A111, &k[0]),
                    (A114, &k[3]),
                    (A115, &k[4]),
                    (A116, &k[5]),
                    (A117, &k[6]),
                    (A118, &k[7]),
                    (A119, &k[8]),
                    (A1110, &k[9]),
                ],
            ),
        );
        let y12 = stage_input(
            y,
            h,
            [
                (A121, &k[0]),
                (A124, &k[3]),
                (A125, &k[4]),
                (A126, &k[5]),
                (A127, &k[6]),
                (A128, &k[7]),
                (A129, &k[8]),
                (A1210, &k[9]),
                (A1211, &k[10]),
            ],
        );
        k[11] = sys.rhs(t + h, &y12);
        self.stage12_input = y12;
        let k = &self.k;
        // The increment `sum b_i k_i`, then `y1 = y + h * increment` as the code does.
        let incr = weighted([
            (B1, &k[0]),
            (B6, &k[5]),
            (B7, &k[6]),
            (B8, &k[7]),
            (B9, &k[8]),
            (B10, &k[9]),
            (B11, &k[10]),
            (B12, &k[11]),
        ]);
        let mut y1 = *y;
        let mut err3 = State::<N>::zeros();
        for n in 0..N {
            y1[n] += h * incr[n];
            err3[n] = h * (incr[n] - BHH1 * k[0][n] - BHH2 * k[8][n] - BHH3 * k[11][n]);
        }
        let err5 = weighted([
            (ER1, &k[0]),
            (ER6, &k[5]),
            (ER7, &k[6]),
            (ER8, &k[7]),
            (ER9, &k[8]),
            (ER10, &k[9]),
            (ER11, &k[10]),
            (ER12, &k[11]),
        ]) * h;
        out.y1 = y1;
        out.f1 = None;
        out.err = Some(err5);
        out.err_low = Some(err3);
        Ok(())
    }

    /// `f(y1)`, the next step's first stage, and the continuous extension's three stages.
    fn complete<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        h: f64,
        a: &mut Attempt<N>,
    ) -> bool {
        let k = &mut self.k;
        k[12] = sys.rhs(t + h, &a.y1);
        a.f1 = Some(k[12]);
        k[13] = sys.rhs(
            t + C14 * h,
            &stage_input(
                y,
                h,
                [
                    (A141, &k[0]),
                    (A147, &k[6]),
                    (A148, &k[7]),
                    (A149, &k[8]),
                    (A1410, &k[9]),
                    (A1411, &k[10]),
                    (A1412, &k[11]),
                    (A1413, &k[12]),
                ],
            ),
        );
        k[14] = sys.rhs(
            t + C15 * h,
            &stage_input(
                y,
                h,
                [
                    (A151, &k[0]),
                    (A156, &k[5]),
                    (A157, &k[6]),
                    (A158, &k[7]),
                    (A1511, &k[10]),
                    (A1512, &k[11]),
                    (A1513, &k[12]),
                    (A1514, &k[13]),
                ],
            ),
        );
        k[15] = sys.rhs(
            t + C16 * h,
            &stage_input(
                y,
                h,
                [
                    (A161, &k[0]),
                    (A166, &k[5]),
                    (A167, &k[6]),
                    (A168, &k[7]),
                    (A169, &k[8]),
                    (A1613, &k[12]),
                    (A1614, &k[13]),
                    (A1615, &k[14]),
                ],
            ),
        );
        true
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        let f1 =
            a.f1.as_ref()
                .expect("a DOP853 step is completed (f(y1)) before its dense output");
        let k = &self.k;
        let ydiff = a.y1 - y0;
        let bspl = f0 * h - ydiff;
        let r4 = ydiff - f1 * h - bspl;
        let row = |d: [f64; 12]| {
            weighted([
                (d[0], &k[0]),
                (d[1], &k[5]),
                (d[2], &k[6]),
                (d[3], &k[7]),
                (d[4], &k[8]),
                (d[5], &k[9]),
                (d[6], &k[10]),
                (d[7], &k[11]),
                (d[8], &k[12]),
                (d[9], &k[13]),
                (d[10], &k[14]),
                (d[11], &k[15]),
            ]) * h
        };
        let r5 = row([
            D41, D46, D47, D48, D49, D410, D411, D412, D413, D414, D415, D416,
        ]);
        let r6 = row([
            D51, D56, D57, D58, D59, D510, D511, D512, D513, D514, D515, D516,
        ]);
        let r7 = row([
            D61, D66, D67, D68, D69, D610, D611, D612, D613, D614, D615, D616,
        ]);
        let r8 = row([
            D71, D76, D77, D78, D79, D710, D711, D712, D713, D714, D715, D716,
        ]);
        DenseOutput::order7(t, h, [*y0, ydiff, bspl, r4, r5, r6, r7, r8])
    }

    fn stiffness_estimate(&self, h: f64, a: &Attempt<N>) -> Option<f64> {
        // Two evaluations at t + h: f(stage 12 input) and f(y1) (Hairer, DOP853).
        crate::stiffness::h_lambda(h, &a.y1, a.f1.as_ref()?, &self.stage12_input, &self.k[11])
    }
}
