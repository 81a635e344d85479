//! Rodas4: the L-stable Rosenbrock method of order 4(3) of Hairer and Wanner's code RODAS, with
//! its continuous extension of order 3, for stiff problems.
//!
//! A Rosenbrock method solves no nonlinear equations: each of its six stages is one linear
//! solve with the same matrix `W = I / (h gamma) - J`, `J = df/dy` at the step's start, so a
//! step costs one Jacobian, one LU factorization of `W` and five evaluations of `f` (plus
//! `f(t + h, y1)` once the step is accepted, the next step's first). In the transformed form
//! of Hairer & Wanner (*Solving ODEs II*, Sec. IV.7) that the code RODAS uses, which needs no
//! matrix-vector product, with `k_i` the stage increments:
//!
//! ```text
//! W k_i = f(t + c_i h, y + sum_{j<i} a_ij k_j) + sum_{j<i} (c_ij / h) k_j + h d_i df/dt
//! ```
//!
//! The last two stages are evaluated at `t + h` and the method is stiffly accurate twice over:
//! `y5 = y + sum a_5j k_j`, the embedded solution `y6 = y5 + k5` (order 3) and the solution
//! `y1 = y6 + k6` (order 4), so the error estimate is `k6` itself. Both are L-stable: the
//! stability function vanishes at infinity, which damps stiff components in one step.
//!
//! The Jacobian is evaluated once per starting point (analytic when the system gives one,
//! [`OdeSystem::jacobian`], else by finite differences) and kept for the attempts that retry
//! from the same point after a rejection, as RODAS does; `W` is factorized for every attempt
//! (its `h` differs). An accepted step or a handler's restart drops the Jacobian.
//!
//! Why this method: its order (4, with an order-3 continuous extension) suits the engine's
//! tolerances (1e-6 to 1e-9); it is Hairer's, so its step sequence can be checked against the
//! published behaviour of RODAS on the classic stiff test problems; and a Rosenbrock method
//! has no Newton iteration whose convergence must be monitored, which keeps the step simple
//! and its cost fixed (one factorization and six solves of size `N` on the stack, `lu.rs`).

use crate::controller::PredictiveController;
use crate::dense::DenseOutput;
use crate::jacobian::{finite_difference_jacobian, finite_difference_time_derivative};
use crate::lu::Lu;
use crate::options::SolverOptions;
use crate::solution::Stats;
use crate::stepper::{Attempt, StepFailure, Stepper};
use crate::system::OdeSystem;
use crate::{Matrix, State};

// Coefficients of RODAS, METH = 1 (Hairer & Wanner, Solving ODEs II, 2nd ed., Sec. VI.4,
// p. 452, and the code RODAS of that book, subroutine ROCOE, to the digits published there). `GAMMA` is the diagonal
// `gamma`; `C2..C4` the nodes (`c5 = c6 = 1`); `D1..D4` the `gamma_i = sum_j gamma_ij` of the
// `df/dt` term (`d5 = d6 = 0`); `Aij`, `Cij` the transformed coefficients of the stage form
// above; `D2j`, `D3j` the continuous extension.
const GAMMA: f64 = 0.25;
const C2: f64 = 0.386;
const C3: f64 = 0.21;
const C4: f64 = 0.63;

const D1: f64 = 0.25;
const D2: f64 = -0.1043;
const D3: f64 = 0.1035;
const D4: f64 = -0.362_000_000_000_002_3e-1;

const A21: f64 = 0.1544e1;
const A31: f64 = 0.946_678_528_081_582_6;
const A32: f64 = 0.255_701_169_898_328_4;
const A41: f64 = 0.331_482_518_706_852_1e1;
const A42: f64 = 0.289_612_401_597_220_1e1;
const A43: f64 = 0.998_641_913_997_781_7;
const A51: f64 = 0.122_122_450_922_664_1e1;
const A52: f64 = 0.601_913_448_128_862_9e1;
const A53: f64 = 0.125_370_833_293_208_7e2;
const A54: f64 = -0.687_886_036_105_895;

const C21: f64 = -0.56688e1;
const C31: f64 = -0.243_009_335_683_387_5e1;
const C32: f64 = -0.206_359_915_709_191_5;
const C41: f64 = -0.107_352_905_815_137_5;
const C42: f64 = -0.959_456_225_102_335_5e1;
const C43: f64 = -0.204_702_861_480_961_6e2;
const C51: f64 = 0.749_644_331_396_764_7e1;
const C52: f64 = -0.102_468_043_146_435_2e2;
const C53: f64 = -0.339_999_035_281_990_5e2;
const C54: f64 = 0.117_089_089_320_616e2;
const C61: f64 = 0.808_324_679_592_152_2e1;
const C62: f64 = -0.798_113_298_806_489_3e1;
const C63: f64 = -0.315_215_943_287_437_1e2;
const C64: f64 = 0.163_193_054_312_313_6e2;
const C65: f64 = -0.605_881_823_883_405_4e1;

const D21: f64 = 0.101_262_350_834_458_6e2;
const D22: f64 = -0.748_799_587_761_016_7e1;
const D23: f64 = -0.348_009_186_155_574_7e2;
const D24: f64 = -0.799_277_170_756_882_3e1;
const D25: f64 = 0.102_513_772_329_566_2e1;
const D31: f64 = -0.676_280_339_280_125_3;
const D32: f64 = 0.608_771_465_168_001_5e1;
const D33: f64 = 0.164_308_432_089_247_8e2;
const D34: f64 = 0.247_672_251_141_838_6e2;
const D35: f64 = -0.659_438_912_571_687_2e1;

/// The Rodas4 stepper. Keeps the Jacobian of the current starting point and the stages of the
/// last attempt (for its dense output).
pub struct Rodas<const N: usize> {
    /// Stage increments `k1..k6` of the last attempt.
    k: [State<N>; 6],
    /// `df/dy` and `df/dt` at the current starting point, when `jacobian_current`.
    jac: Matrix<N>,
    dfdt: State<N>,
    jacobian_current: bool,
    jacobian_evals: u64,
    lu_decompositions: u64,
}

impl<const N: usize> Rodas<N> {
    pub fn new() -> Self {
        Rodas {
            k: [State::<N>::zeros(); 6],
            jac: Matrix::<N>::zeros(),
            dfdt: State::<N>::zeros(),
            jacobian_current: false,
            jacobian_evals: 0,
            lu_decompositions: 0,
        }
    }

    /// `df/dy` at the start of the last attempt.
    pub(crate) fn jacobian(&self) -> &Matrix<N> {
        &self.jac
    }

    /// `df/dy` and `df/dt` at `(t, y)`, where `f0 = f(t, y)`: the system's own where it has
    /// them, else finite differences (`jacobian.rs`).
    fn evaluate_jacobian<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: &State<N>, f0: &State<N>) {
        let (jac, dfdt) = sys.jacobians(t, y);
        self.jac = jac.unwrap_or_else(|| finite_difference_jacobian(sys, t, y, f0));
        self.dfdt = dfdt.unwrap_or_else(|| finite_difference_time_derivative(sys, t, y, f0));
        self.jacobian_current = true;
        self.jacobian_evals += 1;
    }
}

impl<const N: usize> Default for Rodas<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Stepper<N> for Rodas<N> {
    type Controller = PredictiveController;

    fn order(&self) -> u32 {
        4
    }

    fn is_adaptive(&self) -> bool {
        true
    }

    /// RODAS's own controller and constants; the settings' PI constants are DOPRI5's.
    fn controller(&self, _opts: &SolverOptions) -> PredictiveController {
        PredictiveController::rodas()
    }

    fn step_into<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &State<N>,
        f0: &State<N>,
        h: f64,
        out: &mut Attempt<N>,
    ) -> Result<(), StepFailure> {
        if !self.jacobian_current {
            self.evaluate_jacobian(sys, t, y, f0);
        }
        let mut w = -self.jac;
        let diagonal = 1.0 / (h * GAMMA);
        for i in 0..N {
            w[(i, i)] += diagonal;
        }
        self.lu_decompositions += 1;
        let lu = Lu::new(w).ok_or(StepFailure::SingularMatrix)?;
        let solve = |b: State<N>| lu.solve(&b);
        let dt = &self.dfdt;
        let hi = 1.0 / h;

        let k1 = solve(f0 + dt * (h * D1));
        let f = sys.rhs(t + C2 * h, &(y + k1 * A21));
        let k2 = solve(f + dt * (h * D2) + k1 * (C21 * hi));
        let f = sys.rhs(t + C3 * h, &(y + k1 * A31 + k2 * A32));
        let k3 = solve(f + dt * (h * D3) + (k1 * C31 + k2 * C32) * hi);
        let f = sys.rhs(t + C4 * h, &(y + k1 * A41 + k2 * A42 + k3 * A43));
        let k4 = solve(f + dt * (h * D4) + (k1 * C41 + k2 * C42 + k3 * C43) * hi);
        let y5 = y + k1 * A51 + k2 * A52 + k3 * A53 + k4 * A54;
        let f = sys.rhs(t + h, &y5);
        let k5 = solve(f + (k1 * C51 + k2 * C52 + k3 * C53 + k4 * C54) * hi);
        // The embedded solution (order 3).
        let y6 = y5 + k5;
        let f = sys.rhs(t + h, &y6);
        let k6 = solve(f + (k1 * C61 + k2 * C62 + k3 * C63 + k4 * C64 + k5 * C65) * hi);
        self.k = [k1, k2, k3, k4, k5, k6];
        *out = Attempt {
            y1: y6 + k6,
            f1: None,
            err: Some(k6),
            err_low: None,
        };
        Ok(())
    }

    /// RODAS's continuous extension (order 3):
    /// `y(t + theta h) = y0 + theta (y1 - y0) + theta (1 - theta) (r3 + theta r4)`,
    /// `r3 = sum_j d_2j k_j`, `r4 = sum_j d_3j k_j`.
    fn dense(
        &self,
        t: f64,
        h: f64,
        y0: &State<N>,
        _f0: &State<N>,
        a: &Attempt<N>,
    ) -> DenseOutput<N> {
        let [k1, k2, k3, k4, k5, _] = &self.k;
        let r3 = k1 * D21 + k2 * D22 + k3 * D23 + k4 * D24 + k5 * D25;
        let r4 = k1 * D31 + k2 * D32 + k3 * D33 + k4 * D34 + k5 * D35;
        DenseOutput::from_coefficients(t, h, [*y0, a.y1 - y0, r3, r4, State::<N>::zeros()])
    }

    /// Hairer's stiffness test belongs to DOPRI5: an implicit method has no stability limit
    /// to report.
    fn stiffness_estimate(&self, _h: f64, _a: &Attempt<N>) -> Option<f64> {
        None
    }

    fn accepted(&mut self) {
        self.jacobian_current = false;
    }

    fn restart(&mut self) {
        self.jacobian_current = false;
    }

    fn add_counts(&self, stats: &mut Stats) {
        stats.jacobian_evals += self.jacobian_evals;
        stats.lu_decompositions += self.lu_decompositions;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `y' = lambda y` (exact Jacobian and df/dt = 0).
    struct Linear(f64);

    impl OdeSystem<1> for Linear {
        fn rhs(&self, _t: f64, y: &State<1>) -> State<1> {
            y * self.0
        }
        fn jacobian(&self, _t: f64, _y: &State<1>) -> Option<Matrix<1>> {
            Some(Matrix::<1>::new(self.0))
        }
        fn time_derivative(&self, _t: f64, _y: &State<1>) -> Option<State<1>> {
            Some(State::<1>::zeros())
        }
    }

    /// The stability functions of the solution and of the embedded solution at `z = h lambda`.
    fn stability(z: f64) -> (f64, f64) {
        let mut r = Rodas::<1>::new();
        let sys = Linear(z);
        let y = State::<1>::new(1.0);
        let a = r.step(&sys, 0.0, &y, &sys.rhs(0.0, &y), 1.0).unwrap();
        (a.y1[0], a.y1[0] - a.err.unwrap()[0])
    }

    #[test]
    fn orders_four_and_three_on_the_linear_test_equation() {
        // R(z) - e^z = O(z^5) and R_embedded(z) - e^z = O(z^4): halving z divides the
        // differences by 32 and 16.
        let defect = |z: f64| {
            let (r, re) = stability(z);
            ((r - z.exp()).abs(), (re - z.exp()).abs())
        };
        let (a, ae) = defect(-0.02);
        let (b, be) = defect(-0.01);
        let (p, pe) = ((a / b).log2(), (ae / be).log2());
        assert!((p - 5.0).abs() < 0.1, "local order of the solution {p}");
        assert!(
            (pe - 4.0).abs() < 0.1,
            "local order of the embedded solution {pe}"
        );
    }

    #[test]
    fn l_stable_solution_and_embedded_solution() {
        for z in [-1e6, -1e10] {
            let (r, re) = stability(z);
            assert!(r.abs() < 1e-5 && re.abs() < 1e-5, "z = {z}: {r}, {re}");
        }
        for z in [-0.5, -3.0, -30.0, -300.0] {
            let (r, re) = stability(z);
            assert!(r.abs() < 1.0 && re.abs() < 1.0, "z = {z}: {r}, {re}");
        }
    }

    #[test]
    fn dense_output_meets_both_ends() {
        let sys = Linear(-3.0);
        let mut r = Rodas::<1>::new();
        let y = State::<1>::new(1.0);
        let f0 = sys.rhs(0.0, &y);
        let a = r.step(&sys, 0.0, &y, &f0, 0.1).unwrap();
        let d = r.dense(0.0, 0.1, &y, &f0, &a);
        assert_eq!(d.eval(0.0)[0], 1.0);
        assert!((d.eval(0.1)[0] - a.y1[0]).abs() < 1e-16);
        // and is third order inside: error at the middle well below the step's own error
        assert!((d.eval(0.05)[0] - (-0.15f64).exp()).abs() < 1e-6);
    }

    #[test]
    fn jacobian_is_kept_across_rejections_and_dropped_on_acceptance_or_restart() {
        let sys = Linear(-2.0);
        let mut r = Rodas::<1>::new();
        let y = State::<1>::new(1.0);
        let f0 = sys.rhs(0.0, &y);
        r.step(&sys, 0.0, &y, &f0, 0.1).unwrap();
        r.rejected();
        r.step(&sys, 0.0, &y, &f0, 0.05).unwrap();
        assert_eq!((r.jacobian_evals, r.lu_decompositions), (1, 2));
        r.accepted();
        r.step(&sys, 0.05, &y, &f0, 0.05).unwrap();
        r.restart();
        r.step(&sys, 0.05, &y, &f0, 0.05).unwrap();
        assert_eq!((r.jacobian_evals, r.lu_decompositions), (3, 4));
    }

    #[test]
    fn a_singular_iteration_matrix_is_a_failure_not_a_panic() {
        // 1 / (h gamma) = lambda: W = 0.
        let sys = Linear(4.0);
        let mut r = Rodas::<1>::new();
        let y = State::<1>::new(1.0);
        let got = r.step(&sys, 0.0, &y, &sys.rhs(0.0, &y), 1.0);
        assert_eq!(got.unwrap_err(), StepFailure::SingularMatrix);
    }
}
