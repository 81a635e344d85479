//! The Saltelli sample: SALib's row layout (`SALib.sample.sobol.sample`) over the engine's own
//! base points. Each row is a pure function of its number, so a sweep can draw any row alone
//! (a chunk, a shard, a resumed remainder) on any thread.

use crate::error::{config, SensitivityError};

/// What a row of the sample is, within its base point's block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowKind {
    /// The base point's `A` half: columns `0..D` of the Sobol point.
    A,
    /// `AB_j`: `A` with column `j` taken from `B`.
    AB(usize),
    /// `BA_j`: `B` with column `j` taken from `A` (second order only).
    BA(usize),
    /// The base point's `B` half: columns `D..2D` of the Sobol point.
    B,
}

/// A Saltelli sample of `n_base` base points over `n_inputs` inputs.
///
/// Rows come in blocks, one block per base point `i` (rows `i * block .. (i + 1) * block`):
/// `A, AB_1 .. AB_D, [BA_1 .. BA_D,] B`; `block = 2D + 2` with second order, `D + 2` without,
/// as SALib lays them out, so SALib's `analyze.sobol.analyze` reads the outputs in this order.
///
/// The base points are the Owen-scrambled Sobol sequence of `sobol_burley` in `2D` dimensions
/// (point `i`, dimensions `0..D` for `A`, `D..2D` for `B`), seeded; they are not SALib's. The
/// sequence gives 23 bits per coordinate (`k / 2²³`); a unit coordinate here is the centre of its
/// cell, `(k + 1/2) / 2²³`, so it lies strictly inside `(0, 1)` (an inverse CDF never sees 0 or
/// 1) and the truncation is unbiased.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SaltelliSample {
    n_inputs: usize,
    n_base: usize,
    second_order: bool,
    seed: u32,
}

/// Half a cell of the 23-bit grid on which `sobol_burley` returns its coordinates.
const HALF_CELL: f64 = 1.0 / (1u64 << 24) as f64;

impl SaltelliSample {
    /// The most base points (`sobol_burley` draws at most `2¹⁶` points of a sequence).
    pub const MAX_BASE_POINTS: usize = 1 << 16;
    /// The most inputs (`sobol_burley` has 256 dimensions; a base point takes `2D`).
    pub const MAX_INPUTS: usize = sobol_burley::NUM_DIMENSIONS as usize / 2;

    /// A sample of `n_base` base points (a power of two, at most [`Self::MAX_BASE_POINTS`]) for
    /// `n_inputs` inputs (1 to [`Self::MAX_INPUTS`]). `seed` picks the scrambling; a seed of 64
    /// bits is folded to the 32 the sequence takes (`seed ^ (seed >> 32)`, so seeds below `2³²`
    /// are used as they are).
    pub fn new(
        n_inputs: usize,
        n_base: usize,
        second_order: bool,
        seed: u64,
    ) -> Result<SaltelliSample, SensitivityError> {
        if n_inputs == 0 || n_inputs > Self::MAX_INPUTS {
            return Err(config(
                "inputs",
                n_inputs,
                format!("saltelli takes 1 to {} inputs", Self::MAX_INPUTS),
            ));
        }
        if !n_base.is_power_of_two() || n_base > Self::MAX_BASE_POINTS {
            return Err(config(
                "samples",
                n_base,
                format!(
                    "saltelli takes a power of two from 1 to {} base points",
                    Self::MAX_BASE_POINTS
                ),
            ));
        }
        Ok(SaltelliSample {
            n_inputs,
            n_base,
            second_order,
            seed: (seed ^ (seed >> 32)) as u32,
        })
    }

    pub fn n_inputs(&self) -> usize {
        self.n_inputs
    }

    pub fn n_base(&self) -> usize {
        self.n_base
    }

    pub fn second_order(&self) -> bool {
        self.second_order
    }

    /// Rows per base point: `2D + 2` with second order, `D + 2` without.
    pub fn block(&self) -> usize {
        block_len(self.n_inputs, self.second_order)
    }

    /// Rows in all: `N (2D + 2)` or `N (D + 2)`.
    pub fn n_rows(&self) -> u64 {
        self.n_base as u64 * self.block() as u64
    }

    /// The base point of `row` and what the row is within its block.
    pub fn row_kind(&self, row: u64) -> (usize, RowKind) {
        assert!(row < self.n_rows(), "row {row} out of 0..{}", self.n_rows());
        let block = self.block() as u64;
        let base = (row / block) as usize;
        let pos = (row % block) as usize;
        let d = self.n_inputs;
        let kind = if pos == 0 {
            RowKind::A
        } else if pos <= d {
            RowKind::AB(pos - 1)
        } else if pos + 1 < self.block() {
            RowKind::BA(pos - 1 - d)
        } else {
            RowKind::B
        };
        (base, kind)
    }

    /// Coordinate `dim` (`0..2D`) of base point `base`: the Sobol point's unit value.
    pub fn base_coord(&self, base: usize, dim: usize) -> f64 {
        assert!(base < self.n_base && dim < 2 * self.n_inputs);
        sobol_burley::sample(base as u32, dim as u32, self.seed) as f64 + HALF_CELL
    }

    /// The unit point of `row`, one coordinate per input, written into `out` (length `D`).
    pub fn fill_unit_point(&self, row: u64, out: &mut [f64]) {
        let d = self.n_inputs;
        assert_eq!(out.len(), d, "a point of {d} inputs");
        let (base, kind) = self.row_kind(row);
        // Whether column c is taken from B (else from A).
        let from_b = |c: usize| match kind {
            RowKind::A => false,
            RowKind::B => true,
            RowKind::AB(j) => c == j,
            RowKind::BA(j) => c != j,
        };
        for (c, x) in out.iter_mut().enumerate() {
            let dim = if from_b(c) { d + c } else { c };
            *x = self.base_coord(base, dim);
        }
    }

    /// The unit point of `row`, one coordinate per input, each in `(0, 1)`.
    pub fn unit_point(&self, row: u64) -> Vec<f64> {
        let mut out = vec![0.0; self.n_inputs];
        self.fill_unit_point(row, &mut out);
        out
    }
}

/// Rows per base point for `n_inputs` inputs: `2D + 2` with second order, `D + 2` without.
pub fn block_len(n_inputs: usize, second_order: bool) -> usize {
    if second_order {
        2 * n_inputs + 2
    } else {
        n_inputs + 2
    }
}
