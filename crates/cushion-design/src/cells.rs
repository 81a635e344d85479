//! The design space as cells on a lattice: each design range cut into `n` steps (`n` a power of
//! two, so halving a cell keeps its corners on the lattice and a corner shared by two cells is
//! the same design point, run once); a list axis is taken value by value, never split.
//!
//! A lattice point holds one integer per design axis: the step along a range, the value's index
//! along a list. A cell is its lowest corner and its size in steps along every range.

use crate::axes::Axes;

/// A point of the lattice.
pub(crate) type Node = Vec<u32>;

/// A cell: the box from `low` to `low + size` along every range, at `low`'s value along every
/// list. With no range among the design axes a cell is one point (size 0).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cell {
    pub(crate) low: Node,
    pub(crate) size: u32,
}

pub(crate) struct Lattice {
    /// Steps per range.
    pub(crate) n: u32,
    /// Per design axis: whether it is a range.
    pub(crate) continuous: Vec<bool>,
    /// The size of a starting cell (at least 1): design points are filed by the starting cell
    /// they lie in, so a cell finds the points in it among few.
    pub(crate) bucket: u32,
}

impl Lattice {
    /// The normalised coordinates of a lattice point.
    pub(crate) fn coordinates(&self, p: &[u32]) -> Vec<f64> {
        p.iter()
            .zip(&self.continuous)
            .map(|(&i, &c)| {
                if c {
                    i as f64 / self.n as f64
                } else {
                    i as f64
                }
            })
            .collect()
    }

    fn ranges(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.continuous.len()).filter(|&i| self.continuous[i])
    }

    /// The cells of the starting grid: `m` per range (`m` divides `n`), each list value apart.
    pub(crate) fn initial(&self, axes: &Axes, m: u32) -> Vec<Cell> {
        let radix: Vec<u32> = axes
            .axes()
            .iter()
            .map(|a| match a.kind {
                crate::axes::AxisKind::Range { .. } => m,
                crate::axes::AxisKind::Values { count } => count as u32,
            })
            .collect();
        let size = if self.ranges().next().is_some() {
            self.n / m
        } else {
            0
        };
        let total: u32 = radix.iter().product();
        (0..total)
            .map(|mut k| {
                let mut low = vec![0; radix.len()];
                for i in (0..radix.len()).rev() {
                    let j = k % radix[i];
                    k /= radix[i];
                    low[i] = if self.continuous[i] { j * size } else { j };
                }
                Cell { low, size }
            })
            .collect()
    }

    /// A cell's corners: corner `b` lies at the top of the `j`-th range when bit `j` of `b` is set.
    pub(crate) fn corners(&self, c: &Cell) -> Vec<Node> {
        let ranges: Vec<usize> = self.ranges().collect();
        (0..1u32 << ranges.len())
            .map(|b| {
                let mut p = c.low.clone();
                for (j, &i) in ranges.iter().enumerate() {
                    if b >> j & 1 == 1 {
                        p[i] += c.size;
                    }
                }
                p
            })
            .collect()
    }

    /// The cell halved along every range: its `2^d` children, in corner order.
    pub(crate) fn children(&self, c: &Cell) -> Vec<Cell> {
        let half = Cell {
            low: c.low.clone(),
            size: c.size / 2,
        };
        self.corners(&half)
            .into_iter()
            .map(|low| Cell {
                low,
                size: half.size,
            })
            .collect()
    }

    /// Whether the closed cell holds lattice point `p` (corners and points on its faces too).
    pub(crate) fn holds(&self, c: &Cell, p: &[u32]) -> bool {
        (0..p.len()).all(|i| {
            if self.continuous[i] {
                p[i] >= c.low[i] && p[i] <= c.low[i] + c.size
            } else {
                p[i] == c.low[i]
            }
        })
    }

    /// Whether the cell holds position `x` (lattice units along ranges, the index along lists).
    /// Cells are half-open, but the top of the lattice belongs to the last cell, so every
    /// position has exactly one cell.
    pub(crate) fn holds_position(&self, c: &Cell, x: &[f64]) -> bool {
        (0..x.len()).all(|i| {
            if self.continuous[i] {
                let (lo, hi) = (c.low[i] as f64, (c.low[i] + c.size) as f64);
                x[i] >= lo && (x[i] < hi || (x[i] == hi && c.low[i] + c.size == self.n))
            } else {
                x[i] == c.low[i] as f64
            }
        })
    }

    /// The bucket a lattice point is filed in: its starting cell, counted along each range (a
    /// point on an upper face goes to the next one).
    pub(crate) fn bucket_of(&self, p: &[u32]) -> Node {
        p.iter()
            .zip(&self.continuous)
            .map(|(&i, &c)| if c { i / self.bucket } else { i })
            .collect()
    }

    /// The buckets that may hold points of a cell's closed box: its own starting cell's and the
    /// next along each subset of the ranges (for the points on its upper faces).
    pub(crate) fn buckets_near(&self, c: &Cell) -> Vec<Node> {
        let base = Cell {
            low: self.bucket_of(&c.low),
            size: 1,
        };
        self.corners(&base)
    }

    /// The multilinear interpolation at position `x` of values given at the cell's corners
    /// (in [`Lattice::corners`] order).
    pub(crate) fn interpolate(&self, c: &Cell, x: &[f64], at_corners: &[f64]) -> f64 {
        let t: Vec<f64> = self
            .ranges()
            .map(|i| {
                if c.size == 0 {
                    0.0
                } else {
                    (x[i] - c.low[i] as f64) / c.size as f64
                }
            })
            .collect();
        at_corners
            .iter()
            .enumerate()
            .map(|(b, v)| {
                let w: f64 = t
                    .iter()
                    .enumerate()
                    .map(|(j, &t)| if b >> j & 1 == 1 { t } else { 1.0 - t })
                    .product();
                w * v
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axes::Axis;

    #[test]
    fn cells_split_hold_and_interpolate() {
        let axes = Axes::new(
            "design",
            vec![
                Axis::range("x", 0.0, 1.0),
                Axis::values("m", 2),
                Axis::range("y", 0.0, 1.0),
            ],
        )
        .unwrap();
        let l = Lattice {
            n: 8,
            continuous: vec![true, false, true],
            bucket: 4,
        };
        let cells = l.initial(&axes, 2);
        assert_eq!(cells.len(), 8);
        assert_eq!(
            cells[7],
            Cell {
                low: vec![4, 1, 4],
                size: 4
            }
        );
        let c = &cells[0];
        assert_eq!(
            l.corners(c),
            vec![vec![0, 0, 0], vec![4, 0, 0], vec![0, 0, 4], vec![4, 0, 4]]
        );
        assert_eq!(l.children(c).len(), 4);
        assert!(l.holds(c, &[2, 0, 4]) && !l.holds(c, &[2, 1, 4]) && !l.holds(c, &[5, 0, 0]));
        // Half-open, except at the top of the lattice.
        assert!(!l.holds_position(c, &[4.0, 0.0, 1.0]));
        assert!(l.holds_position(&cells[5], &[8.0, 0.0, 8.0]));
        // Bilinear: corner values 0, 1, 2, 3 are x/4 + 2 y/4.
        let v = l.interpolate(c, &[1.0, 0.0, 3.0], &[0.0, 1.0, 2.0, 3.0]);
        assert!((v - (0.25 + 1.5)).abs() < 1e-15);
        // A child of the last cell files its points in that cell's bucket and the next ones.
        let child = &l.children(&cells[5])[3];
        assert_eq!(l.bucket_of(&child.low), vec![1, 0, 1]);
        assert_eq!(l.buckets_near(child).len(), 4);
        assert_eq!(l.bucket_of(&[8, 0, 8]), vec![2, 0, 2]);
    }
}
