//! Tests of the peak rule on sampled functions: a tracker fed the samples, each top it asks for
//! searched by Brent's method (`tracker.rs`, `search.rs`).

use super::sampler::K;
use super::search::*;
use super::tracker::*;
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

/// Sample `f` four times per step of 0.01 over `[0, 1]`, searching each top the tracker asks
/// for on `f` itself (split at the step's start, as the sampler does), and the open top at
/// the end: the peak, `(t, value)`, and how many tops were searched.
fn peak_of(f: impl Fn(f64) -> f64) -> (f64, f64, usize) {
    let mut p = PeakTracker::starting_at(
        Peak {
            t: 0.0,
            value: f(0.0),
            reported: f(0.0),
        },
        top_window(1e-6),
    );
    let mut searched = 0;
    let mut locate = |p: &mut PeakTracker, b: Bracket, split: f64| {
        searched += 1;
        let (t, value, _) = search(b, split, &f, &f);
        p.found(Peak {
            t,
            value,
            reported: value,
        });
    };
    let h = 0.01;
    for i in 0..100 {
        let t0 = i as f64 * h;
        for k in 1..=K {
            let t = t0 + h * k as f64 / K as f64;
            if let Some(b) = p.sample(t, f(t)) {
                locate(&mut p, b, t0);
            }
        }
    }
    if let Some(b) = p.open_top() {
        locate(&mut p, b, f64::INFINITY);
    }
    (p.peak.t, p.peak.value, searched)
}

#[test]
fn a_top_at_a_step_end_is_searched_on_both_sides() {
    // tops 1e-4 before and 1e-4 after the step end at 0.5 (a sample), each side's in its step
    for tp in [0.4999, 0.5001] {
        let (t, v, searched) = peak_of(|t| 2.0 - 300.0 * (t - tp) * (t - tp));
        assert!((t - tp).abs() < 1e-7, "{t} for {tp}");
        assert!((v - 2.0).abs() < 1e-13, "{v}");
        assert_eq!(searched, 1);
    }
}

#[test]
fn a_quantity_rising_to_the_end_peaks_at_the_end() {
    let (t, v, _) = peak_of(|t| t * t + 0.5);
    assert_eq!((t, v), (1.0, 1.5));
}

#[test]
fn a_top_before_a_plateau_is_found() {
    // a rise that overshoots to 1.001 at 0.5012 and settles at 0.502 on 1.0 for good: the
    // samples from 0.5025 on are all 1.0, the largest sample, and the top lies before them
    let f = |t: f64| {
        if t < 0.502 {
            1.001 - 1.0e3 * (t - 0.5012) * (t - 0.5012)
        } else {
            1.0
        }
    };
    assert!(f(0.5) < 1.0);
    let (t, v, searched) = peak_of(f);
    assert!((t - 0.5012).abs() < 1e-7, "{t}");
    assert!((v - 1.001).abs() < 1e-13, "{v}");
    assert_eq!(searched, 1);
}

#[test]
fn tops_far_below_the_largest_value_are_not_searched() {
    // a decaying ringing: the first top at 0.05 (height 1) is searched; the later ones are
    // more than the 1 % window below it
    let (t, v, searched) = peak_of(|t| (-3.0 * t).exp() * (10.0 * std::f64::consts::PI * t).sin());
    assert!(searched <= 2, "{searched} searches");
    let tp = (10.0 * std::f64::consts::PI / 3.0).atan() / (10.0 * std::f64::consts::PI);
    let top = (-3.0 * tp).exp() * (10.0 * std::f64::consts::PI * tp).sin();
    assert!((t - tp).abs() < 1e-7 && (v - top).abs() < 1e-14, "{t} {v}");
}

#[test]
fn of_two_peaks_of_the_same_height_the_earlier_is_the_peak() {
    // two quadratic peaks (exact in the quartic nodes) at 0.2033 and 0.6913, of height 1
    // and 1 + 2e-13: the same height to the search's rounding (~1e-15) and within `TIE`,
    // though the later one is the larger and is found so (without the rule it would win)
    let bump = |t: f64, tp: f64| 1.0 - 40.0 * (t - tp) * (t - tp);
    let f = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 2e-13).max(0.0);
    let (t, v, _) = peak_of(f);
    assert!((t - 0.2033).abs() < 1e-6, "{t}");
    assert!((v - 1.0).abs() < 1e-14, "{v}");
    // a later peak higher by more than the tie's width is the peak
    let g = |t: f64| bump(t, 0.2033).max(bump(t, 0.6913) + 1e-9).max(0.0);
    let (t, _, _) = peak_of(g);
    assert!((t - 0.6913).abs() < 1e-6, "{t}");
}

#[test]
fn a_peak_sampled_low_among_several_near_ones_is_still_found() {
    // Three sharp peaks: at 0.20125 (height 1.003, its nearest node 1.25e-3 away, so its
    // two samples, at 0.2 and 0.2025, are both 0.99675), at 0.4 (1.0, on a node) and at 0.601
    // (1.001, sample 0.997). The middle one holds the largest sample; the first holds the
    // peak, with the smallest sample of the three, and its top lies between two equal ones.
    let bump = |t: f64, tp: f64, top: f64| top - 4000.0 * (t - tp) * (t - tp);
    let f = |t: f64| {
        bump(t, 0.20125, 1.003)
            .max(bump(t, 0.4, 1.0))
            .max(bump(t, 0.601, 1.001))
            .max(0.0)
    };
    let (t, v, _) = peak_of(f);
    assert!((t - 0.20125).abs() < 1e-6, "{t}");
    assert!((v - 1.003).abs() < 1e-12, "{v}");
}

#[test]
fn a_higher_top_before_a_shallow_dip_is_found() {
    // Two tops 0.1 apart with a dip of 0.3 % between them (less than the window): the first,
    // 1.25e-3 from its nearest node, is higher by 3e-6 but sampled 7.5e-6 low; the second
    // sits on a node. The second's sample is the largest: the first top must be searched,
    // though by its sample it is not the peak.
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
    let (t, v, _) = peak_of(f);
    assert!((t - t_top).abs() < 1e-5, "{t} vs {t_top}");
    assert!((v - top).abs() < 1e-13, "{v} vs {top}");
}
