//! The verification grid and the check of its runs.

use cushion_design::{check, verify_grid, Axes, Axis, Limit, Limits};

fn for_all() -> Axes {
    Axes::new(
        "for_all",
        vec![
            Axis::range("mass", 0.1, 1.0),
            Axis::log_range("dead_time", 0.001, 0.1),
            Axis::values("k", 2),
        ],
    )
    .unwrap()
}

#[test]
fn the_grid_has_n_points_per_range_and_every_list_value() {
    let points = verify_grid(&for_all(), 41).unwrap();
    assert_eq!(points.len(), 41 * 41 * 2);
    assert_eq!(points[0], vec![0.1, 0.001, 0.0]);
    assert_eq!(points[points.len() - 1], vec![1.0, 0.1, 1.0]);
    // The dead time is spread evenly in its logarithm: the middle of 41 points is 0.01.
    assert!((points[20 * 2][1] - 0.01).abs() < 1e-15, "{:?}", points[40]);
    assert!(verify_grid(&for_all(), 1).is_err());
    assert!(
        verify_grid(&for_all(), 10_000).is_err(),
        "2 x 10^8 runs: refused"
    );
}

#[test]
fn the_check_finds_the_worst_case_and_counts_violations() {
    let limits = Limits::new(
        vec![Limit::max("force", 40.0).abs(), Limit::max("speed", 1.3)],
        None,
    )
    .unwrap();
    let points = verify_grid(&for_all(), 11).unwrap();
    // Force -50 m (signed), speed 10 dead_time + k / 10: worst force -50 N at m = 1 (over by
    // 25 %), worst speed 1.1 m/s at the longest dead time with k = 1.
    let model = |p: &[f64]| vec![-50.0 * p[0], 10.0 * p[1] + p[2] / 10.0];
    let rows: Vec<Vec<f64>> = points.iter().map(|p| model(p)).collect();
    let v = check(&limits, &points, &rows).unwrap();
    assert!(!v.all_met);
    // Masses over 0.8 kg exceed 40 N: 0.82, 0.91 and 1.0 of the 11-point grid.
    assert_eq!(v.violations, 3 * 11 * 2);
    assert_eq!(v.worst[0].value, -50.0);
    assert_eq!(v.worst[0].witness[0], 1.0);
    assert!((v.worst[1].value - 1.1).abs() < 1e-12 && v.worst[1].witness[1..] == [0.1, 1.0]);
    assert!((v.margin + 0.25).abs() < 1e-12);
    assert_eq!(v.runs, points.len());

    // Within the limits everywhere, then one failed run.
    let mut rows: Vec<Vec<f64>> = points.iter().map(|p| vec![-30.0 * p[0], p[1]]).collect();
    let ok = check(&limits, &points, &rows).unwrap();
    assert!(ok.all_met && ok.violations == 0 && ok.margin > 0.0);
    rows[7] = vec![f64::NAN, f64::NAN];
    let bad = check(&limits, &points, &rows).unwrap();
    assert!(!bad.all_met && bad.violations == 1 && bad.failed == 1);
    assert!(bad.worst.iter().all(|w| w.failed && w.witness == points[7]));
    assert!(check(&limits, &points, &rows[1..]).is_err());
}
