//! Dormand–Prince 5(4) with its coefficients as constants: the same method as
//! [`crate::stepper::ExplicitRk`] reading [`DORMAND_PRINCE_54`](crate::tableau::DORMAND_PRINCE_54),
//! and the same numbers to the last bit, but with no tableau read at run time, no branch on zero
//! coefficients and no temporaries: each stage combination is one pass over the components.
//!
//! Bit-identity with the generic stepper rests on doing the same operations in the same order:
//! every combination is `((y + k_a (h a)) + k_b (h b)) + ...` with the terms in tableau order,
//! zero coefficients left out, exactly as `ExplicitRk` skips them. The tests at the bottom check
//! the constants against the tableau and the results against `ExplicitRk`.

use crate::controller::PiController;
use crate::dense::DenseOutput;
use crate::options::SolverOptions;
use crate::stepper::{Attempt, StepFailure, Stepper};
use crate::system::OdeSystem;
use crate::State;

// Nodes, written as in the tableau so that they are the same `f64`s.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;

// Weights of the solution (b2 = 0).
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;

// Error weights `b - b_hat` over k1..k6, f1 (e2 = 0).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

// Hairer's dense-output weights over k1..k6, f1 (d2 = 0).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// `base + k_1 (h w_1) + k_2 (h w_2) + ...`, added left to right, component by component.
#[inline(always)]
fn add_scaled<const N: usize, const M: usize>(
    base: &State<N>,
    h: f64,
    terms: [(f64, &State<N>); M],
) -> State<N> {
    let hw = terms.map(|(w, _)| h * w);
    let mut out = *base;
    for n in 0..N {
        let mut acc = out[n];
        for m in 0..M {
            acc += terms[m].1[n] * hw[m];
        }
        out[n] = acc;
    }
    out
}

/// `k_1 (h w_1) + k_2 (h w_2) + ...`, added left to right (the first term is not added to zero,
/// so a `-0.0` stays `-0.0` as in the generic stepper).
#[inline(always)]
fn scaled_sum<const N: usize, const M: usize>(h: f64, terms: [(f64, &State<N>); M]) -> State<N> {
    let hw = terms.map(|(w, _)| h * w);
    let mut out = State::<N>::zeros();
    for n in 0..N {
        let mut acc = terms[0].1[n] * hw[0];
        for m in 1..M {
            acc += terms[m].1[n] * hw[m];
        }
        out[n] = acc;
    }
    out
}

/// DOPRI5 with constant coefficients. Keeps the stages of the last attempt for its dense
/// output and the stiffness test.
pub struct Dopri5<const N: usize> {
    /// Stages k2..k6 (k1 is the `f0` the caller passes in).
    k: [State<N>; 5],
    /// Input of stage 6 (at `t + h`), for the stiffness test.
    stage6_input: State<N>,
}

impl<const N: usize> Dopri5<N> {
    pub fn new() -> Self {
        Dopri5 {
            k: [State::<N>::zeros(); 5],
            stage6_input: State::<N>::zeros(),
        }
    }
}

impl<const N: usize> Default for Dopri5<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Stepper<N> for Dopri5<N> {
    type Controller = PiController;

    fn order(&self) -> u32 {
        5
    }

    fn is_adaptive(&self) -> bool {
        true
    }

    /// Hairer's PI controller with the settings' constants (DOPRI5's by default).
    fn controller(&self, opts: &SolverOptions) -> PiController {
        PiController::new(5, opts.safety, opts.beta, opts.min_ratio, opts.max_ratio)
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
        let k1 = f0;
        let k2 = sys.rhs(t + C2 * h, &add_scaled(y, h, [(A21, k1)]));
        let k3 = sys.rhs(t + C3 * h, &add_scaled(y, h, [(A31, k1), (A32, &k2)]));
        let k4 = sys.rhs(
            t + C4 * h,
            &add_scaled(y, h, [(A41, k1), (A42, &k2), (A43, &k3)]),
        );
        let k5 = sys.rhs(
            t + C5 * h,
            &add_scaled(y, h, [(A51, k1), (A52, &k2), (A53, &k3), (A54, &k4)]),
        );
        let y6 = add_scaled(
            y,
            h,
            [(A61, k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
        );
        // c6 = 1: `t + 1.0 * h` is `t + h`.
        let k6 = sys.rhs(t + h, &y6);
        let y1 = add_scaled(y, h, [(B1, k1), (B3, &k3), (B4, &k4), (B5, &k5), (B6, &k6)]);
        let f1 = sys.rhs(t + h, &y1);
        let err = scaled_sum(
            h,
            [
                (E7, &f1),
                (E1, k1),
                (E3, &k3),
                (E4, &k4),
                (E5, &k5),
                (E6, &k6),
            ],
        );
        self.k = [k2, k3, k4, k5, k6];
        self.stage6_input = y6;
        out.y1 = y1;
        out.f1 = Some(f1);
        out.err = Some(err);
        out.err_low = None;
        Ok(())
    }

    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        let (y1, f1) = (
            &a.y1,
            a.f1.as_ref().expect("a DOPRI5 attempt carries f1 (FSAL)"),
        );
        let [_, k3, k4, k5, k6] = &self.k;
        let r5 = scaled_sum(
            h,
            [(D7, f1), (D1, f0), (D3, k3), (D4, k4), (D5, k5), (D6, k6)],
        );
        DenseOutput::new(t, h, y0, y1, f0, f1, r5)
    }

    fn stiffness_estimate(&self, h: f64, a: &Attempt<N>) -> Option<f64> {
        // Two evaluations at t + h: f(stage 6 input) and f(y1) (Hairer, DOPRI5).
        crate::stiffness::h_lambda(h, &a.y1, a.f1.as_ref()?, &self.stage6_input, &self.k[4])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stepper::{Counted, ExplicitRk};
    use crate::tableau::DORMAND_PRINCE_54 as T;
    use crate::test_models::arenstorf::{initial_state, Arenstorf};
    use crate::test_models::van_der_pol::VanDerPol;

    #[test]
    fn constants_are_the_tableau_bit_for_bit() {
        let same = |a: f64, b: f64| assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
        for (c, tc) in [C2, C3, C4, C5, 1.0].iter().zip(&T.c[1..]) {
            same(*c, *tc);
        }
        let a: [&[f64]; 5] = [
            &[A21],
            &[A31, A32],
            &[A41, A42, A43],
            &[A51, A52, A53, A54],
            &[A61, A62, A63, A64, A65],
        ];
        for (row, trow) in a.iter().zip(&T.a[1..]) {
            assert_eq!(row.len(), trow.len());
            for (x, tx) in row.iter().zip(trow.iter()) {
                same(*x, *tx);
            }
        }
        for (x, tx) in [B1, 0.0, B3, B4, B5, B6].iter().zip(T.b) {
            same(*x, *tx);
        }
        for (x, tx) in [E1, 0.0, E3, E4, E5, E6, E7].iter().zip(T.e) {
            same(*x, *tx);
        }
        for (x, tx) in [D1, 0.0, D3, D4, D5, D6, D7].iter().zip(T.d) {
            same(*x, *tx);
        }
        assert_eq!(T.order, 5);
        assert_eq!((T.b.len(), T.e.len(), T.d.len()), (6, 7, 7));
    }

    fn bits<const N: usize>(v: &State<N>) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// Attempts, dense output and stiffness estimate agree with the generic stepper bit for bit.
    fn agrees_with_generic<S: OdeSystem<N>, const N: usize>(sys: &S, y: State<N>, hs: &[f64]) {
        let mut fast = Dopri5::<N>::new();
        let mut generic = ExplicitRk::<N>::new(&T);
        let (sys_a, sys_b) = (Counted::new(sys), Counted::new(sys));
        let t = 0.3;
        let f0 = sys.rhs(t, &y);
        for &h in hs {
            let a = fast.step(&sys_a, t, &y, &f0, h).unwrap();
            let b = generic.step(&sys_b, t, &y, &f0, h).unwrap();
            assert_eq!(bits(&a.y1), bits(&b.y1), "y1, h = {h}");
            assert_eq!(bits(&a.f1.unwrap()), bits(&b.f1.unwrap()), "f1, h = {h}");
            assert_eq!(bits(&a.err.unwrap()), bits(&b.err.unwrap()), "err, h = {h}");
            // The dense output's own step may differ from h in the last bits (t1 - t).
            let hd = (t + h) - t;
            let da = fast.dense(t, hd, &y, &f0, &a);
            let db = generic.dense(t, hd, &y, &f0, &b);
            for theta in [0.0, 0.2, 0.5, 0.77, 1.0] {
                let tt = t + theta * hd;
                assert_eq!(
                    bits(&da.eval(tt)),
                    bits(&db.eval(tt)),
                    "dense at theta {theta}, h = {h}"
                );
            }
            let (sa, sb) = (
                fast.stiffness_estimate(h, &a),
                generic.stiffness_estimate(h, &b),
            );
            assert_eq!(
                sa.map(f64::to_bits),
                sb.map(f64::to_bits),
                "stiffness, h = {h}"
            );
        }
        // Six evaluations an attempt (stages 2..6 and f1), counted as they are made.
        assert_eq!(sys_a.evals(), sys_b.evals());
        assert_eq!(sys_a.evals(), 6 * hs.len() as u64);
        assert_eq!(fast.order(), generic.order());
    }

    #[test]
    fn same_bits_as_the_generic_stepper() {
        let hs = [1e-6, 1e-3, 0.0137, 0.1, 0.7];
        agrees_with_generic(&Arenstorf, initial_state(), &hs);
        agrees_with_generic(&VanDerPol { mu: 1000.0 }, State::<2>::new(2.0, -0.6), &hs);
        agrees_with_generic(&VanDerPol { mu: 1.0 }, State::<2>::new(-0.0, 0.0), &hs);
    }
}
