//! Forward-mode differentiation by hand: [`D`] is a value with its derivatives along `W`
//! directions. The Jacobian (`jacobian.rs`) runs the physics with seven directions, one per
//! dynamic state and time, and gets every partial derivative; the peaks (`rates.rs`) run it
//! with one direction, the solution's own velocity `(y', 1)`, and get each quantity's rate of
//! change along the run.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value and its derivatives along `W` directions.
#[derive(Clone, Copy, Debug)]
pub(super) struct D<const W: usize> {
    pub v: f64,
    pub g: [f64; W],
}

impl<const W: usize> D<W> {
    pub fn constant(v: f64) -> D<W> {
        D { v, g: [0.0; W] }
    }

    /// A variable at value `v` whose derivatives along the directions are `seed`.
    pub fn var(v: f64, seed: [f64; W]) -> D<W> {
        D { v, g: seed }
    }

    /// `f(self)` with `f' = slope` at `self.v`.
    pub fn chain(self, v: f64, slope: f64) -> D<W> {
        D {
            v,
            g: self.g.map(|x| x * slope),
        }
    }

    /// `d^1.5` for `d > 0`, else 0.
    pub fn pos15(self) -> D<W> {
        if self.v > 0.0 {
            let r = self.v.sqrt();
            self.chain(self.v * r, 1.5 * r)
        } else {
            D::constant(0.0)
        }
    }
}

impl<const W: usize> Add for D<W> {
    type Output = D<W>;
    fn add(self, o: D<W>) -> D<W> {
        D {
            v: self.v + o.v,
            g: std::array::from_fn(|i| self.g[i] + o.g[i]),
        }
    }
}

impl<const W: usize> Sub for D<W> {
    type Output = D<W>;
    fn sub(self, o: D<W>) -> D<W> {
        self + (-o)
    }
}

impl<const W: usize> Neg for D<W> {
    type Output = D<W>;
    fn neg(self) -> D<W> {
        self * -1.0
    }
}

// The product and quotient rules: clippy's suspicion of `+` in `Mul` does not apply.
#[allow(clippy::suspicious_arithmetic_impl)]
impl<const W: usize> Mul for D<W> {
    type Output = D<W>;
    fn mul(self, o: D<W>) -> D<W> {
        D {
            v: self.v * o.v,
            g: std::array::from_fn(|i| self.g[i] * o.v + self.v * o.g[i]),
        }
    }
}

impl<const W: usize> Mul<f64> for D<W> {
    type Output = D<W>;
    fn mul(self, k: f64) -> D<W> {
        D {
            v: self.v * k,
            g: self.g.map(|x| x * k),
        }
    }
}

#[allow(clippy::suspicious_arithmetic_impl)]
impl<const W: usize> Div for D<W> {
    type Output = D<W>;
    fn div(self, o: D<W>) -> D<W> {
        let q = self.v / o.v;
        D {
            v: q,
            g: std::array::from_fn(|i| (self.g[i] - q * o.g[i]) / o.v),
        }
    }
}

impl<const W: usize> Div<f64> for D<W> {
    type Output = D<W>;
    fn div(self, k: f64) -> D<W> {
        self * (1.0 / k)
    }
}
