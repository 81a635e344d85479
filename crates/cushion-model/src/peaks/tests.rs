//! Tests of `peaks.rs`.

use super::*;
use std::cell::Cell;

#[test]
fn brent_finds_a_smooth_peak_to_round_off_in_few_evaluations() {
    // f = cos(t - 0.3) peaks at 0.3 with value 1; start from a sample at 0.25
    let calls = Cell::new(0);
    let f = |t: f64| {
        calls.set(calls.get() + 1);
        (t - 0.3).cos()
    };
    let (t, v) = brent_max(f, 0.2, 0.45, (0.25, (0.25f64 - 0.3).cos()));
    assert!((t - 0.3).abs() < 1e-7, "{t}");
    assert!((v - 1.0).abs() < 1e-14, "{v}");
    assert!(calls.get() <= 20, "{} evaluations", calls.get());
}

#[test]
fn brent_returns_the_bracket_end_for_a_monotone_function() {
    let (t, v) = brent_max(|t| t * t, 1.0, 2.0, (1.5, 2.25));
    assert!((t - 2.0).abs() < 1e-6, "{t}");
    assert!((v - 4.0).abs() < 1e-5, "{v}");
}

#[test]
fn brent_keeps_the_start_when_nothing_is_larger() {
    // a kink peak at the start point itself
    let (t, v) = brent_max(|t: f64| 1.0 - (t - 0.5).abs(), 0.0, 1.0, (0.5, 1.0));
    assert_eq!((t, v), (0.5, 1.0));
}

#[test]
fn lagrange_nodes_reproduce_a_quartic() {
    let q = |t: f64| 1.0 + t - 2.0 * t * t + 0.5 * t.powi(3) - 0.25 * t.powi(4);
    let (step, _, _) = step_of(&q, 0.1, 0.2);
    for t in [0.1, 0.13, 0.2, 0.29] {
        assert!((step.state_at(t)[0] - q(t)).abs() < 1e-14);
    }
}

/// A step of `f` over `[t0, t0 + h]`: its five nodes, its largest sample marked.
fn step_of(f: &impl Fn(f64) -> f64, t0: f64, h: f64) -> (PeakStep, f64, f64) {
    let ts: [f64; K + 1] = std::array::from_fn(|k| t0 + h * k as f64 / K as f64);
    let mut nodes = [[0.0; MAX_DYNAMIC]; K + 1];
    let mut k_best = 0;
    for k in 0..=K {
        nodes[k][0] = f(ts[k]);
        if nodes[k][0] > nodes[k_best][0] {
            k_best = k;
        }
    }
    let step = PeakStep {
        ts,
        nodes,
        seg: Segment {
            t0: 0.0,
            x0: 0.0,
            v0: 0.0,
            a: 0.0,
            phase: crate::physics::Phase::Stopped,
        },
        regime: Regime::default(),
        k: k_best,
    };
    (step, nodes[k_best][0], nodes[K][0])
}

/// Observe `f` step by step over `[0, 1]` and locate its peak: `(t, value)`.
fn peak_of(f: impl Fn(f64) -> f64) -> (f64, f64) {
    let mut c = PeakCandidate::starting_at(f(0.0), RIVAL);
    let h = 0.01;
    for i in 0..100 {
        let (step, best, end) = step_of(&f, i as f64 * h, h);
        c.observe(best, end, || step);
        if c.wants_next() {
            c.follow(step_of(&f, (i + 1) as f64 * h, h).0);
        }
    }
    let (t, v, _) = c.locate(|c, t| c.state_at(t)[0], c.best).unwrap();
    (t, v)
}

#[test]
fn of_two_peaks_of_the_same_height_the_earlier_is_the_peak() {
    // two quadratic peaks (exact in the quartic nodes) at 0.2033 and 0.6913, of height 1
    // and 1 + 2e-13: the same height to the search's rounding (~1e-15) and within `TIE`,
    // though the later one is the larger and is found so (without the rule it would win)
    let bump = |t: f64, tp: f64| 1.0 - 40.0 * (t - tp) * (t - tp);
    let f = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 2e-13).max(0.0);
    let (t, v) = peak_of(f);
    assert!((t - 0.2033).abs() < 1e-6, "{t}");
    assert!((v - 1.0).abs() < 1e-14, "{v}");
    // a later peak higher by more than the tie's width is the peak
    let g = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 1e-9).max(0.0);
    let (t, _) = peak_of(g);
    assert!((t - 0.6913).abs() < 1e-6, "{t}");
}

#[test]
fn a_peak_sampled_low_among_several_near_ones_is_still_found() {
    // Three sharp peaks: at 0.20125 (height 1.003, its nearest node 1.25e-3 away, so its
    // largest sample is 0.99675), at 0.4 (1.0, on a node) and at 0.601 (1.001, sample
    // 0.997). The middle one holds the largest sample; the first holds the peak, with the
    // smallest sample of the three: one rival slot would have kept the last one only.
    let bump = |t: f64, tp: f64, top: f64| top - 4000.0 * (t - tp) * (t - tp);
    let f = |t: f64| {
        bump(t, 0.20125, 1.003)
            .max(bump(t, 0.4, 1.0))
            .max(bump(t, 0.601, 1.001))
            .max(0.0)
    };
    let (t, v) = peak_of(f);
    assert!((t - 0.20125).abs() < 1e-6, "{t}");
    assert!((v - 1.003).abs() < 1e-12, "{v}");
}

#[test]
fn a_higher_top_before_a_shallow_dip_is_found() {
    // Two tops 0.1 apart with a dip of 0.3 % between them (less than `RIVAL`): the first,
    // 1.25e-3 from its nearest node, is higher by 3e-6 but sampled 7.5e-6 low; the second
    // sits on a node. The second's sample is the largest, and without a dip of `RIVAL` the
    // two count as one peak: the first top's step must still be searched.
    let (left, right): (f64, f64) = (0.45125, 0.55);
    let (m, d) = (0.5 * (left + right), 0.5 * (right - left));
    let a = 0.003 / d.powi(4);
    let b = 3e-6 / (2.0 * d);
    let f = |t: f64| {
        let u = (t - m) * (t - m) - d * d;
        1.0 - a * u * u - b * (t - m)
    };
    // the true top, by a fine scan and a search around it
    let t_top = (0..=100_000)
        .map(|i| i as f64 * 1e-5)
        .max_by(|x, y| f(*x).total_cmp(&f(*y)))
        .unwrap();
    assert!((t_top - left).abs() < 1e-4, "{t_top}");
    let (_, top) = brent_max(f, t_top - 1e-4, t_top + 1e-4, (t_top, f(t_top)));
    // the larger sample is the right top's
    assert!(f(right) > f(0.4525).max(f(0.45)));
    let (t, v) = peak_of(f);
    assert!((t - t_top).abs() < 1e-5, "{t} vs {t_top}");
    assert!((v - top).abs() < 1e-13, "{v} vs {top}");
}
