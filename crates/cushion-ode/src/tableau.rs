//! Butcher tableaus as data. One generic explicit Runge–Kutta stepper ([`crate::stepper`])
//! reads them.
//!
//! Every tableau lists its stages `k_1..k_s` (`k_1 = f(t, y)`); after them the stepper always
//! evaluates `f1 = f(t + h, y1)`, which is both the FSAL stage of Dormand–Prince (stage 7) and
//! the first stage of the next step for every method. The error weights `e` and the dense
//! output weights `d` run over `k_1..k_s, f1`.

/// A Butcher tableau with optional embedded error estimate and dense output.
#[derive(Debug)]
pub struct Tableau {
    pub name: &'static str,
    /// Order of the propagated solution.
    pub order: u32,
    /// Nodes `c_1..c_s`.
    pub c: &'static [f64],
    /// Row `i` holds `a_{i,1..i-1}` (row 0 is empty).
    pub a: &'static [&'static [f64]],
    /// Weights of the propagated solution over `k_1..k_s`.
    pub b: &'static [f64],
    /// Error weights `b - b_hat` over `k_1..k_s, f1`; empty for fixed-step methods.
    pub e: &'static [f64],
    /// Weights of the extra dense-output term (Hairer's `d`) over `k_1..k_s, f1`; empty means
    /// the cubic Hermite interpolant from `y0, y1, f0, f1`.
    pub d: &'static [f64],
}

/// Dormand–Prince 5(4) (Hairer, Nørsett, Wanner, Solving ODEs I, table 5.2; DOPRI5).
pub static DORMAND_PRINCE_54: Tableau = Tableau {
    name: "dp5",
    order: 5,
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0],
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
    e: &[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ],
    d: &[
        -12715105075.0 / 11282082432.0,
        0.0,
        87487479700.0 / 32700410799.0,
        -10690763975.0 / 1880347072.0,
        701980252875.0 / 199316789632.0,
        -1453857185.0 / 822651844.0,
        69997945.0 / 29380423.0,
    ],
};

/// Classical fourth-order Runge–Kutta.
pub static CLASSICAL_RK4: Tableau = Tableau {
    name: "rk4",
    order: 4,
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    e: &[],
    d: &[],
};

/// Explicit Euler.
pub static EXPLICIT_EULER: Tableau = Tableau {
    name: "euler",
    order: 1,
    c: &[0.0],
    a: &[&[]],
    b: &[1.0],
    e: &[],
    d: &[],
};

/// Most stages of any tableau here.
pub const MAX_STAGES: usize = 6;

#[cfg(test)]
mod tests {
    use super::*;

    fn check_consistency(t: &Tableau) {
        let s = t.c.len();
        assert_eq!(t.a.len(), s);
        assert_eq!(t.b.len(), s);
        assert!(s <= MAX_STAGES);
        for (i, row) in t.a.iter().enumerate() {
            assert_eq!(row.len(), i);
            let sum: f64 = row.iter().sum();
            assert!(
                (sum - t.c[i]).abs() < 1e-14,
                "{} row {i}: sum a = {sum} != c",
                t.name
            );
        }
        let sb: f64 = t.b.iter().sum();
        assert!((sb - 1.0).abs() < 1e-14, "{}: sum b = {sb}", t.name);
        if !t.e.is_empty() {
            assert_eq!(t.e.len(), s + 1);
            let se: f64 = t.e.iter().sum();
            assert!(se.abs() < 1e-14, "{}: error weights sum to {se}", t.name);
        }
    }

    #[test]
    fn tableaus_are_consistent() {
        check_consistency(&DORMAND_PRINCE_54);
        check_consistency(&CLASSICAL_RK4);
        check_consistency(&EXPLICIT_EULER);
    }

    #[test]
    fn dp5_order_conditions_up_to_five() {
        // sum b c^(q-1) = 1/q for q = 1..5 (the bushy-tree conditions).
        let t = &DORMAND_PRINCE_54;
        for q in 1..=5 {
            let s: f64 = t.b.iter().zip(t.c).map(|(b, c)| b * c.powi(q - 1)).sum();
            assert!((s - 1.0 / q as f64).abs() < 1e-14, "q = {q}: {s}");
        }
    }
}
