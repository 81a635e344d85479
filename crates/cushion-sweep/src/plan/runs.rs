//! Which runs of a sweep one call computes: all of them, a shard (`run % N == K - 1`), or a
//! contiguous range (the unit a Dask task or a batch job takes). Every selection is an
//! arithmetic progression of run numbers, so a selection of billions of runs costs nothing.

use crate::error::SweepError;

/// Run numbers `first, first + step, ...`, `len` of them, ascending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Runs {
    first: u64,
    step: u64,
    len: u64,
}

impl Runs {
    /// Every run of a sweep of `n_runs`.
    pub fn all(n_runs: u64) -> Runs {
        Runs {
            first: 0,
            step: 1,
            len: n_runs,
        }
    }

    /// Shard `k` of `n` (1-based `k`): the runs with `run % n == k - 1`, interleaved so that
    /// each shard gets a fair share of every part of a grid.
    pub fn shard(n_runs: u64, k: usize, n: usize) -> Result<Runs, SweepError> {
        if n == 0 || k == 0 || k > n {
            return Err(SweepError::Config(format!(
                "shard {k}/{n}: K must be from 1 to N"
            )));
        }
        let (k, n) = (k as u64, n as u64);
        let len = if n_runs < k { 0 } else { (n_runs - k) / n + 1 };
        Ok(Runs {
            first: k - 1,
            step: n,
            len,
        })
    }

    /// The runs `start..stop` of a sweep of `n_runs`.
    pub fn range(n_runs: u64, start: u64, stop: u64) -> Result<Runs, SweepError> {
        if start > stop || stop > n_runs {
            return Err(SweepError::Config(format!(
                "runs {start}..{stop}: need 0 <= start <= stop <= {n_runs} (the sweep's run count)"
            )));
        }
        Ok(Runs {
            first: start,
            step: 1,
            len: stop - start,
        })
    }

    /// How many runs.
    pub fn len(&self) -> u64 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The `i`-th run number of the selection (`i < len`).
    pub fn get(&self, i: u64) -> u64 {
        self.first + i * self.step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_runs() {
        let n_runs = 23;
        let mut seen = vec![0; n_runs as usize];
        for k in 1..=4 {
            let r = Runs::shard(n_runs, k, 4).unwrap();
            for i in 0..r.len() {
                let run = r.get(i);
                assert_eq!(run % 4, k as u64 - 1);
                seen[run as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "{seen:?}");
        assert_eq!(Runs::shard(2, 4, 4).unwrap().len(), 0);
        assert!(Runs::shard(10, 0, 4).is_err());
        assert!(Runs::shard(10, 5, 4).is_err());
    }

    #[test]
    fn a_range_is_contiguous_and_checked() {
        let r = Runs::range(10, 3, 7).unwrap();
        assert_eq!(
            (0..r.len()).map(|i| r.get(i)).collect::<Vec<_>>(),
            [3, 4, 5, 6]
        );
        assert!(Runs::range(10, 7, 3).is_err());
        assert!(Runs::range(10, 3, 11).is_err());
        assert!(Runs::range(10, 10, 10).unwrap().is_empty());
    }
}
