//! The Saltelli sample: row counts, what each row is, the A/B/AB/BA relations, the base points'
//! source and stratification, seeds, and the limits.

use cushion_sensitivity::{block_len, RowKind, SaltelliSample};

#[test]
fn row_counts() {
    for d in [1, 2, 4, 7] {
        for n in [1, 2, 64, 1 << 14] {
            let with = SaltelliSample::new(d, n, true, 0).unwrap();
            let without = SaltelliSample::new(d, n, false, 0).unwrap();
            assert_eq!(with.n_rows(), (n * (2 * d + 2)) as u64);
            assert_eq!(without.n_rows(), (n * (d + 2)) as u64);
            assert_eq!(with.block(), block_len(d, true));
            assert_eq!(without.block(), block_len(d, false));
        }
    }
    // D = 4, N = 2^14, second order: the 163,840 runs.
    assert_eq!(
        SaltelliSample::new(4, 1 << 14, true, 0).unwrap().n_rows(),
        163_840
    );
}

#[test]
fn row_kinds_in_salib_order() {
    let s = SaltelliSample::new(3, 4, true, 0).unwrap();
    use RowKind::*;
    let block = [A, AB(0), AB(1), AB(2), BA(0), BA(1), BA(2), B];
    for row in 0..s.n_rows() {
        assert_eq!(
            s.row_kind(row),
            ((row / 8) as usize, block[(row % 8) as usize])
        );
    }
    let s = SaltelliSample::new(3, 4, false, 0).unwrap();
    let block = [A, AB(0), AB(1), AB(2), B];
    for row in 0..s.n_rows() {
        assert_eq!(
            s.row_kind(row),
            ((row / 5) as usize, block[(row % 5) as usize])
        );
    }
}

/// `AB_j` is `A` with column `j` from `B`; `BA_j` is `B` with column `j` from `A`; `A` and `B`
/// are the two halves of the base point's Sobol point.
#[test]
fn ab_and_ba_rows_mix_a_and_b() {
    for second_order in [true, false] {
        let d = 4;
        let s = SaltelliSample::new(d, 32, second_order, 9).unwrap();
        let block = s.block() as u64;
        for base in 0..s.n_base() {
            let row = |k: u64| s.unit_point(base as u64 * block + k);
            let a = row(0);
            let b = row(block - 1);
            for c in 0..d {
                assert_eq!(a[c], s.base_coord(base, c));
                assert_eq!(b[c], s.base_coord(base, d + c));
                assert_ne!(a[c], b[c]);
            }
            for j in 0..d {
                let ab = row(1 + j as u64);
                for c in 0..d {
                    assert_eq!(ab[c], if c == j { b[c] } else { a[c] }, "AB_{j}[{c}]");
                }
                if second_order {
                    let ba = row(1 + (d + j) as u64);
                    for c in 0..d {
                        assert_eq!(ba[c], if c == j { a[c] } else { b[c] }, "BA_{j}[{c}]");
                    }
                }
            }
        }
    }
}

/// The base points are `sobol_burley::sample` (the sweep's `sobol` mode's sequence) moved to the
/// centres of their 2^-23 cells; every coordinate lies strictly inside (0, 1).
#[test]
fn base_points_are_sobol_burley_cell_centres() {
    let s = SaltelliSample::new(5, 256, true, 12345).unwrap();
    for base in 0..256 {
        for dim in 0..10 {
            let u = s.base_coord(base, dim);
            let raw = sobol_burley::sample(base as u32, dim as u32, 12345) as f64;
            assert_eq!(u, raw + 0.5 / (1u64 << 23) as f64);
            assert!(u > 0.0 && u < 1.0);
        }
    }
}

/// The first N points of each of the 2D columns are stratified: one in each of the N intervals
/// `[k/N, (k+1)/N)` (a property of the Sobol sequence that Owen scrambling keeps), and every
/// pair of columns is a (0, m, 2)-net in base 2 for the first two dimensions.
#[test]
fn base_columns_are_stratified() {
    for (n, seed) in [(16usize, 0u64), (1024, 1), (1 << 14, 77)] {
        let d = 3;
        let s = SaltelliSample::new(d, n, true, seed).unwrap();
        for dim in 0..2 * d {
            let mut seen = vec![false; n];
            for base in 0..n {
                let k = (s.base_coord(base, dim) * n as f64) as usize;
                assert!(
                    !seen[k],
                    "N={n} dim {dim}: two points in [{k}/N, {}/N)",
                    k + 1
                );
                seen[k] = true;
            }
        }
        // Dimensions 0 and 1 (Sobol's first two): every elementary box of area 1/N holds one.
        let m = n.trailing_zeros();
        for split in 0..=m {
            let (nx, ny) = (1usize << split, 1usize << (m - split));
            let mut count = vec![0u8; n];
            for base in 0..n {
                let x = (s.base_coord(base, 0) * nx as f64) as usize;
                let y = (s.base_coord(base, 1) * ny as f64) as usize;
                count[x * ny + y] += 1;
            }
            assert!(count.iter().all(|&c| c == 1), "N={n}: boxes {nx} x {ny}");
        }
    }
}

#[test]
fn rows_are_pure_functions_of_their_number_and_seed() {
    let s = SaltelliSample::new(4, 1024, true, 3).unwrap();
    let forward: Vec<Vec<f64>> = (0..s.n_rows()).map(|r| s.unit_point(r)).collect();
    for r in (0..s.n_rows()).rev().step_by(97) {
        assert_eq!(s.unit_point(r), forward[r as usize]);
    }
    let again = SaltelliSample::new(4, 1024, true, 3).unwrap();
    assert_eq!(again.unit_point(9_999), forward[9_999]);
    // Another seed, other points; a 64-bit seed folds to the 32 bits the sequence takes.
    let other = SaltelliSample::new(4, 1024, true, 4).unwrap();
    assert_ne!(other.unit_point(9_999), forward[9_999]);
    let high = SaltelliSample::new(4, 1024, true, 3 | (7 << 32)).unwrap();
    assert_ne!(high.unit_point(9_999), forward[9_999]);
    // Without second order the same base points, in shorter blocks.
    let first = SaltelliSample::new(4, 1024, false, 3).unwrap();
    assert_eq!(first.unit_point(6 * 10), forward[10 * 10]);
    assert_eq!(first.unit_point(6 * 10 + 5), forward[10 * 10 + 9]);
}

#[test]
fn limits_are_named() {
    let err = |d, n| SaltelliSample::new(d, n, true, 0).unwrap_err().to_string();
    let m = err(3, 1000);
    assert!(
        m.contains("samples = 1000") && m.contains("power of two"),
        "{m}"
    );
    let m = err(3, 1 << 17);
    assert!(m.contains("samples = 131072") && m.contains("65536"), "{m}");
    assert!(err(3, 0).contains("samples = 0"));
    let m = err(0, 8);
    assert!(m.contains("inputs = 0") && m.contains("1 to 128"), "{m}");
    assert!(err(129, 8).contains("inputs = 129"));
    assert!(SaltelliSample::new(128, 1 << 16, true, 0).is_ok());
}
