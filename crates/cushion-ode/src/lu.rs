//! LU factorization with partial pivoting of a fixed-size matrix on the stack, for the
//! Rosenbrock method's `I / (h gamma) - J`.
//!
//! It works on nalgebra's `SMatrix` but is not nalgebra's `LU`: that type needs
//! `Const<N>: DimMin<Const<N>>`, which nalgebra provides for each concrete `N` through typenum
//! but which a generic `const N` cannot show, so using it would put that bound on
//! [`crate::solve`] and on every caller generic over the state's size. The algorithm is the
//! textbook one (Golub & Van Loan, *Matrix Computations*, Alg. 3.4.1; LINPACK's DGEFA/DGESL,
//! as in Hairer's DEC/SOL): for each column the largest entry in magnitude is the pivot,
//! rows are swapped, and the multipliers are stored below the diagonal. A zero (or NaN)
//! pivot means singular.

use crate::{Matrix, State};

/// `P A = L U`, with `L` unit lower triangular (below the diagonal of `lu`) and `U` upper
/// triangular (on and above it); row `i` of `P A` is row `perm[i]` of `A`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lu<const N: usize> {
    lu: Matrix<N>,
    perm: [usize; N],
}

impl<const N: usize> Lu<N> {
    /// Factorize `a`; `None` if it is singular (a zero pivot) or not finite.
    pub fn new(mut a: Matrix<N>) -> Option<Self> {
        let mut perm = [0usize; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        for k in 0..N {
            let mut p = k;
            let mut largest = a[(k, k)].abs();
            for i in k + 1..N {
                let v = a[(i, k)].abs();
                if v > largest {
                    largest = v;
                    p = i;
                }
            }
            if !(largest > 0.0 && largest.is_finite()) {
                return None;
            }
            if p != k {
                a.swap_rows(k, p);
                perm.swap(k, p);
            }
            let inv = 1.0 / a[(k, k)];
            for i in k + 1..N {
                let l = a[(i, k)] * inv;
                a[(i, k)] = l;
                if l != 0.0 {
                    for j in k + 1..N {
                        a[(i, j)] -= l * a[(k, j)];
                    }
                }
            }
        }
        Some(Lu { lu: a, perm })
    }

    /// `x` with `A x = b`.
    #[inline]
    pub fn solve(&self, b: &State<N>) -> State<N> {
        let lu = &self.lu;
        let mut x = State::<N>::zeros();
        for i in 0..N {
            x[i] = b[self.perm[i]];
        }
        for i in 1..N {
            let mut s = x[i];
            for j in 0..i {
                s -= lu[(i, j)] * x[j];
            }
            x[i] = s;
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for j in i + 1..N {
                s -= lu[(i, j)] * x[j];
            }
            x[i] = s / lu[(i, i)];
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_like_nalgebras_lu() {
        // A matrix that needs pivoting (zero in the first diagonal place).
        let a = Matrix::<4>::new(
            0.0, 2.0, -1.0, 3.0, //
            4.0, 1.0, 0.5, -2.0, //
            -1.0, 3.0, 2.0, 1.0, //
            2.0, -1.0, 5.0, 0.25,
        );
        let b = State::<4>::new(1.0, -2.0, 0.5, 3.0);
        let x = Lu::new(a).unwrap().solve(&b);
        let want = a.lu().solve(&b).unwrap();
        assert!((x - want).amax() < 1e-14, "{x} vs {want}");
        assert!((a * x - b).amax() < 1e-14);
    }

    #[test]
    fn singular_and_non_finite_matrices_are_refused() {
        let singular = Matrix::<3>::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(singular).is_none());
        let mut nan = Matrix::<3>::identity();
        nan[(1, 1)] = f64::NAN;
        assert!(Lu::new(nan).is_none());
    }

    #[test]
    fn one_by_one() {
        let lu = Lu::new(Matrix::<1>::new(4.0)).unwrap();
        assert_eq!(lu.solve(&State::<1>::new(2.0))[0], 0.5);
    }
}
