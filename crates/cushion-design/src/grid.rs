//! A grid over a box: the product of each axis's grid (`n` points of a range, every value of a
//! list), numbered with the first axis slowest. The worst-case search starts from the coarse
//! grid and needs each grid point's neighbours along the ranges; verification runs a fine one.

use crate::axes::Axes;
use crate::error::{config, DesignError};

/// The points of a grid, in normalised coordinates, and how they neighbour.
pub(crate) struct Grid {
    /// Per axis: its grid coordinates.
    along: Vec<Vec<f64>>,
    /// Per axis: whether neighbours along it are meaningful (a range; list values are unordered).
    continuous: Vec<bool>,
}

impl Grid {
    /// `n` points per range, every value of each list.
    pub(crate) fn new(axes: &Axes, n: usize) -> Grid {
        Grid {
            along: axes.axes().iter().map(|a| a.grid(n)).collect(),
            continuous: axes.axes().iter().map(|a| a.is_continuous()).collect(),
        }
    }

    /// Points of the grid of `n` per range over `axes`; `None` beyond `usize`.
    pub(crate) fn count(axes: &Axes, n: usize) -> Option<usize> {
        axes.axes()
            .iter()
            .try_fold(1usize, |k, a| k.checked_mul(a.grid(n).len().max(1)))
    }

    /// An error unless the grid has at most `cap` points: the grid is built in memory, and
    /// a few list axes of many values multiply quickly.
    pub(crate) fn check_size(
        axes: &Axes,
        n: usize,
        key: &str,
        cap: usize,
    ) -> Result<(), DesignError> {
        match Grid::count(axes, n) {
            Some(k) if k <= cap => Ok(()),
            k => Err(config(
                key,
                n,
                format!(
                    "a grid of at most {cap} points ({} here)",
                    k.map_or("more than usize".to_string(), |k| k.to_string())
                ),
            )),
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.along.iter().map(Vec::len).product()
    }

    /// Per-axis indices of point `k`.
    fn indices(&self, mut k: usize) -> Vec<usize> {
        let mut idx = vec![0; self.along.len()];
        for (i, a) in self.along.iter().enumerate().rev() {
            idx[i] = k % a.len();
            k /= a.len();
        }
        idx
    }

    fn number(&self, idx: &[usize]) -> usize {
        self.along
            .iter()
            .zip(idx)
            .fold(0, |k, (a, &i)| k * a.len() + i)
    }

    /// The normalised coordinates of point `k`.
    pub(crate) fn point(&self, k: usize) -> Vec<f64> {
        let idx = self.indices(k);
        self.along.iter().zip(idx).map(|(a, i)| a[i]).collect()
    }

    /// Every point, in order.
    pub(crate) fn points(&self) -> Vec<Vec<f64>> {
        (0..self.len()).map(|k| self.point(k)).collect()
    }

    /// The numbers of point `k`'s neighbours one grid step away along each range.
    pub(crate) fn neighbours(&self, k: usize) -> Vec<usize> {
        let idx = self.indices(k);
        let mut out = Vec::new();
        for (i, a) in self.along.iter().enumerate() {
            if !self.continuous[i] {
                continue;
            }
            for j in [idx[i].wrapping_sub(1), idx[i] + 1] {
                if j < a.len() {
                    let mut m = idx.clone();
                    m[i] = j;
                    out.push(self.number(&m));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axes::Axis;

    #[test]
    fn points_neighbours_and_numbering_agree() {
        let axes = Axes::new(
            "for_all",
            vec![
                Axis::range("a", 0.0, 1.0),
                Axis::values("b", 2),
                Axis::range("c", 0.0, 1.0),
            ],
        )
        .unwrap();
        let g = Grid::new(&axes, 3);
        assert_eq!(g.len(), 18);
        assert_eq!(g.point(0), vec![0.0, 0.0, 0.0]);
        assert_eq!(g.point(1), vec![0.0, 0.0, 0.5]);
        assert_eq!(g.point(3), vec![0.0, 1.0, 0.0]);
        assert_eq!(g.point(17), vec![1.0, 1.0, 1.0]);
        // Point (0.5, 0, 0.5) = number 7: neighbours along a (1, 13) and c (6, 8), not along b.
        let mut n = g.neighbours(7);
        n.sort();
        assert_eq!(n, vec![1, 6, 8, 13]);
    }
}
