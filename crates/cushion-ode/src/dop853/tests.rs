//! DOP853's unit tests: order conditions, estimators, stability boundary, one step.

use super::*;

/// The Butcher tableau of the 12 stages (and the dense output's 16), from the constants.
fn tableau() -> (Vec<f64>, Vec<Vec<f64>>) {
    let mut a = vec![vec![0.0; 16]; 16];
    let mut set = |i: usize, entries: &[(usize, f64)]| {
        for &(j, v) in entries {
            a[i - 1][j - 1] = v;
        }
    };
    set(2, &[(1, A21)]);
    set(3, &[(1, A31), (2, A32)]);
    set(4, &[(1, A41), (3, A43)]);
    set(5, &[(1, A51), (3, A53), (4, A54)]);
    set(6, &[(1, A61), (4, A64), (5, A65)]);
    set(7, &[(1, A71), (4, A74), (5, A75), (6, A76)]);
    set(8, &[(1, A81), (4, A84), (5, A85), (6, A86), (7, A87)]);
    set(
        9,
        &[(1, A91), (4, A94), (5, A95), (6, A96), (7, A97), (8, A98)],
    );
    set(
        10,
        &[
            (1, A101),
            (4, A104),
            (5, A105),
            (6, A106),
            (7, A107),
            (8, A108),
            (9, A109),
        ],
    );
    set(
        11,
        &[
            (1, A111),
            (4, A114),
            (5, A115),
            (6, A116),
            (7, A117),
            (8, A118),
            (9, A119),
            (10, A1110),
        ],
    );
    set(
        12,
        &[
            (1, A121),
            (4, A124),
            (5, A125),
            (6, A126),
            (7, A127),
            (8, A128),
            (9, A129),
            (10, A1210),
            (11, A1211),
        ],
    );
    // stage 13 is f(y1): its row is b
    set(
        13,
        &[
            (1, B1),
            (6, B6),
            (7, B7),
            (8, B8),
            (9, B9),
            (10, B10),
            (11, B11),
            (12, B12),
        ],
    );
    set(
        14,
        &[
            (1, A141),
            (7, A147),
            (8, A148),
            (9, A149),
            (10, A1410),
            (11, A1411),
            (12, A1412),
            (13, A1413),
        ],
    );
    set(
        15,
        &[
            (1, A151),
            (6, A156),
            (7, A157),
            (8, A158),
            (11, A1511),
            (12, A1512),
            (13, A1513),
            (14, A1514),
        ],
    );
    set(
        16,
        &[
            (1, A161),
            (6, A166),
            (7, A167),
            (8, A168),
            (9, A169),
            (13, A1613),
            (14, A1614),
            (15, A1615),
        ],
    );
    let c = vec![
        0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, 1.0, 1.0, C14, C15, C16,
    ];
    (c, a)
}

/// Rooted trees up to order 8, each as the list of its children (indices of smaller trees).
fn trees(max_order: usize) -> Vec<(usize, Vec<usize>)> {
    // (order, children); trees[0] is the single node
    let mut all: Vec<(usize, Vec<usize>)> = vec![(1, vec![])];
    for n in 2..=max_order {
        // multisets of trees (non-decreasing indices) with orders summing to n - 1
        let existing = all.len();
        let mut out = Vec::new();
        fn extend(
            all: &[(usize, Vec<usize>)],
            limit: usize,
            start: usize,
            left: usize,
            cur: &mut Vec<usize>,
            out: &mut Vec<Vec<usize>>,
        ) {
            if left == 0 {
                out.push(cur.clone());
                return;
            }
            for i in start..limit {
                if all[i].0 <= left {
                    cur.push(i);
                    extend(all, limit, i, left - all[i].0, cur, out);
                    cur.pop();
                }
            }
        }
        extend(&all, existing, 0, n - 1, &mut Vec::new(), &mut out);
        for children in out {
            all.push((n, children));
        }
    }
    all
}

/// `g(t)_i` for every tree (the stage vector whose weighted sum is the elementary weight)
/// and `gamma(t)`, over the first `s` stages.
fn elementary(s: usize, a: &[Vec<f64>], trees: &[(usize, Vec<usize>)]) -> Vec<(Vec<f64>, f64)> {
    let mut out: Vec<(Vec<f64>, f64)> = Vec::new();
    for (order, children) in trees {
        let mut g = vec![1.0; s];
        let mut gamma = *order as f64;
        for &ch in children {
            let (gc, gammac) = &out[ch];
            gamma *= gammac;
            for i in 0..s {
                let agc: f64 = (0..s).map(|j| a[i][j] * gc[j]).sum();
                g[i] *= agc;
            }
        }
        out.push((g, gamma));
    }
    out
}

#[test]
fn tree_counts() {
    let t = trees(8);
    let count = |n: usize| t.iter().filter(|x| x.0 == n).count();
    assert_eq!(
        (1..=8).map(count).collect::<Vec<_>>(),
        [1, 1, 2, 4, 9, 20, 48, 115]
    );
}

#[test]
fn nodes_are_the_row_sums() {
    let (c, a) = tableau();
    for i in 1..16 {
        let sum: f64 = a[i].iter().sum();
        assert!(
            (sum - c[i]).abs() < 1e-14,
            "row {}: {sum} vs {}",
            i + 1,
            c[i]
        );
    }
    assert!((C6 - 1.0 / 3.0).abs() < 1e-16 && (C8 - 4.0 / 13.0).abs() < 1e-16);
    assert!((C9 - 127.0 / 195.0).abs() < 1e-16 && (C11 - 6.0 / 7.0).abs() < 1e-16);
    assert!((C16 - 7.0 / 9.0).abs() < 1e-16);
}

#[test]
fn order_conditions_up_to_eight() {
    let (_, a) = tableau();
    let t = trees(8);
    let el = elementary(12, &a, &t);
    let b = &a[12][..12];
    let mut worst = 0.0f64;
    for ((order, _), (g, gamma)) in t.iter().zip(&el) {
        let phi: f64 = b.iter().zip(g).map(|(b, g)| b * g).sum();
        let defect = (phi * gamma - 1.0).abs();
        worst = worst.max(defect);
        assert!(defect < 1e-12, "order {order}: defect {defect:e}");
    }
    println!("largest defect of the 200 conditions: {worst:e}");
    // The order is exactly 8: some condition of order 9 fails.
    let t9 = trees(9);
    let el9 = elementary(12, &a, &t9);
    let worst9 = t9
        .iter()
        .zip(&el9)
        .filter(|((o, _), _)| *o == 9)
        .map(|(_, (g, gamma))| {
            (b.iter().zip(g).map(|(b, g)| b * g).sum::<f64>() * gamma - 1.0).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst9 > 1e-6, "{worst9}");
}

#[test]
fn embedded_estimators_are_of_orders_five_and_three() {
    let (_, a) = tableau();
    let t = trees(6);
    let el = elementary(12, &a, &t);
    let mut er = [0.0; 12];
    for (j, v) in [
        (0, ER1),
        (5, ER6),
        (6, ER7),
        (7, ER8),
        (8, ER9),
        (9, ER10),
        (10, ER11),
        (11, ER12),
    ] {
        er[j] = v;
    }
    let mut e3 = a[12][..12].to_vec();
    e3[0] -= BHH1;
    e3[8] -= BHH2;
    e3[11] -= BHH3;
    let mut fails = [false; 7];
    for ((order, _), (g, gamma)) in t.iter().zip(&el) {
        let d5: f64 = er.iter().zip(g).map(|(e, g)| e * g).sum::<f64>() * gamma;
        let d3: f64 = e3.iter().zip(g).map(|(e, g)| e * g).sum::<f64>() * gamma;
        if *order <= 5 {
            assert!(
                d5.abs() < 1e-12,
                "5th-order estimator, order {order}: {d5:e}"
            );
        } else if d5.abs() > 1e-6 {
            fails[*order] = true;
        }
        if *order <= 3 {
            assert!(
                d3.abs() < 1e-12,
                "3rd-order estimator, order {order}: {d3:e}"
            );
        } else if *order == 4 && d3.abs() > 1e-6 {
            fails[4] = true;
        }
    }
    assert!(fails[6] && fails[4], "the estimators' orders are exact");
}

#[test]
fn stability_boundary() {
    // gamma_j = b^T A^(j-1) 1 of the 12-stage method
    let (_, a) = tableau();
    let b = &a[12][..12];
    let mut v = vec![1.0; 12];
    let mut gamma = vec![1.0];
    for _ in 1..=12 {
        gamma.push(b.iter().zip(&v).map(|(b, v)| b * v).sum());
        v = (0..12)
            .map(|i| (0..12).map(|j| a[i][j] * v[j]).sum())
            .collect();
    }
    let mut fact = 1.0;
    for (j, g) in gamma.iter().enumerate().take(9).skip(1) {
        fact *= j as f64;
        assert!((g * fact - 1.0).abs() < 1e-12, "gamma_{j}");
    }
    let r = |z: f64| gamma.iter().rev().fold(0.0, |acc, g| acc * z + g);
    // bisection on |R(-x)| = 1 between 5 and 7
    let (mut lo, mut hi) = (5.0, 7.0);
    assert!(r(-lo).abs() < 1.0 && r(-hi).abs() > 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if r(-mid).abs() < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    println!("gamma 9..12: {:?}; boundary {lo:.15}", &gamma[9..]);
    // stable everywhere on [-boundary, 0]
    for i in 1..=1000 {
        assert!(r(-lo * i as f64 / 1000.0).abs() <= 1.0 + 1e-12);
    }
    assert!(
        (lo - STABILITY_BOUNDARY).abs() < 1e-12,
        "{lo} vs {STABILITY_BOUNDARY}"
    );
    assert!((STIFFNESS_THRESHOLD - 0.9 * lo).abs() < 1e-12);
}
