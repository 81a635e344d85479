//! The worst-case search on functions whose worst case is known in closed form: the worst found
//! comes within the tolerance of it, never beyond it (it is a real run), and its witness gives
//! the value back to the bit.

use crate::common::{drive_search, Order};
use cushion_design::{
    Axes, Axis, DesignError, Direction, SearchSettings, Target, WorstCaseSearch, WorstCases,
};

const TOL: f64 = 1e-3;

/// x in [2, 6] (linear), y in [0.01, 1] (log): a box whose normalised coordinates are not its
/// real ones, so the tests also check the mapping.
fn box_xy() -> Axes {
    Axes::new(
        "for_all",
        vec![Axis::range("x", 2.0, 6.0), Axis::log_range("y", 0.01, 1.0)],
    )
    .unwrap()
}

/// The normalised coordinates of a point of `box_xy`.
fn uv(p: &[f64]) -> (f64, f64) {
    ((p[0] - 2.0) / 4.0, (p[1] / 0.01).ln() / 100f64.ln())
}

fn target(metric: usize, direction: Direction) -> Target {
    Target { metric, direction }
}

/// The worst cases of `f` (a function of the `for_all` point) over `for_all`, and the runs.
fn worst_of(for_all: Axes, targets: Vec<Target>, f: &dyn Fn(&[f64]) -> Vec<f64>) -> WorstCases {
    let metrics = targets.iter().map(|t| t.metric + 1).max().unwrap();
    let mut s = WorstCaseSearch::new(for_all, targets, metrics, SearchSettings::default()).unwrap();
    let id = s.add(vec![]);
    let model = |_: &[f64], p: &[f64]| f(p);
    drive_search(&mut s, &model, Order::InOrder);
    let w = s.result(id).expect("finished");
    assert_eq!(w.runs, s.runs());
    w
}

fn narrow_peak(p: &[f64]) -> f64 {
    let (u, v) = uv(p);
    1.0 + 9.0 * (-((u - 0.37).powi(2) + (v - 0.61).powi(2)) / (2.0 * 0.06f64.powi(2))).exp()
}

#[test]
fn a_narrow_interior_peak_between_grid_points_is_found() {
    // The 5-point grid straddles the peak: its best point sees 1.23 of the peak's 10.
    let grid = Axes::new(
        "g",
        vec![Axis::range("x", 2.0, 6.0), Axis::log_range("y", 0.01, 1.0)],
    )
    .unwrap();
    let grid_max = (0..5)
        .flat_map(|i| (0..5).map(move |j| (i as f64 / 4.0, j as f64 / 4.0)))
        .map(|(u, v)| narrow_peak(&grid.real(&[u, v])))
        .fold(0.0, f64::max);
    assert!(grid_max < 1.3, "{grid_max}");
    let w = worst_of(box_xy(), vec![target(0, Direction::Max)], &|p| {
        vec![narrow_peak(p)]
    });
    let found = &w.worst[0];
    assert!(
        found.value >= 10.0 * (1.0 - TOL) && found.value <= 10.0,
        "{found:?}"
    );
    assert_eq!(narrow_peak(&found.witness).to_bits(), found.value.to_bits());
    let (u, v) = uv(&found.witness);
    assert!(
        (u - 0.37).abs() < 0.01 && (v - 0.61).abs() < 0.01,
        "{u} {v}"
    );
    // A 201 x 201 grid (40,401 runs) finds no worse, with two orders of magnitude more runs.
    let dense = (0..=200)
        .flat_map(|i| (0..=200).map(move |j| (i as f64 / 200.0, j as f64 / 200.0)))
        .map(|(u, v)| narrow_peak(&grid.real(&[u, v])))
        .fold(0.0, f64::max);
    assert!(
        found.value >= dense * (1.0 - TOL),
        "{} vs {dense}",
        found.value
    );
    assert!(w.runs < 200, "{} runs", w.runs);
}

#[test]
fn a_ridge_along_an_edge_is_followed_on_the_edge() {
    // Worst on the edge y = 1 (v = 1), at u = 0.43: 2 * 2 = 4.
    let ridge = |p: &[f64]| {
        let (u, v) = uv(p);
        vec![(1.0 + v) * (2.0 - 3.0 * (u - 0.43).powi(2))]
    };
    let w = worst_of(box_xy(), vec![target(0, Direction::Max)], &ridge);
    let found = &w.worst[0];
    assert!(
        found.value >= 4.0 * (1.0 - TOL) && found.value <= 4.0,
        "{found:?}"
    );
    assert_eq!(found.witness[1], 1.0, "on the edge, exactly");
    assert_eq!(ridge(&found.witness)[0].to_bits(), found.value.to_bits());
}

#[test]
fn a_kink_minimum_is_found() {
    // The smallest value of 1 + |u - a| + |v - b| / 2 is 1, at a kink off the grid.
    let kink = |p: &[f64]| {
        let (u, v) = uv(p);
        vec![1.0 + (u - 0.3137).abs() + 0.5 * (v - 0.771).abs()]
    };
    let w = worst_of(box_xy(), vec![target(0, Direction::Min)], &kink);
    let found = &w.worst[0];
    assert!(
        found.value <= 1.0 * (1.0 + TOL) && found.value >= 1.0,
        "{found:?}"
    );
    assert_eq!(kink(&found.witness)[0].to_bits(), found.value.to_bits());
}

#[test]
fn the_largest_size_keeps_its_sign() {
    // A signed force: a trough of -4 at (0.7, 0.2) and a peak of 2 at (0.2, 0.8).
    let force = |p: &[f64]| {
        let (u, v) = uv(p);
        let bump = |a: f64, b: f64| (-((u - a).powi(2) + (v - b).powi(2)) / 0.02).exp();
        vec![-4.0 * bump(0.7, 0.2) + 2.0 * bump(0.2, 0.8)]
    };
    let w = worst_of(
        box_xy(),
        vec![target(0, Direction::AbsMax), target(0, Direction::Max)],
        &force,
    );
    let (size, top) = (&w.worst[0], &w.worst[1]);
    assert!(
        size.value < 0.0 && size.value.abs() >= 4.0 * (1.0 - TOL),
        "{size:?}"
    );
    assert!(
        top.value >= 2.0 * (1.0 - TOL) && top.value <= 2.0 + 1e-12,
        "{top:?}"
    );
    assert_eq!(force(&size.witness)[0].to_bits(), size.value.to_bits());
}

#[test]
fn a_list_axis_is_searched_value_by_value() {
    // Three values, each with its own peak along x: heights 1, 3, 2 at 0.2, 0.71, 0.5.
    let for_all = Axes::new(
        "for_all",
        vec![Axis::range("x", 0.0, 1.0), Axis::values("k", 3)],
    )
    .unwrap();
    let f = |p: &[f64]| {
        let (h, a) = [(1.0, 0.2), (3.0, 0.71), (2.0, 0.5)][p[1] as usize];
        vec![h * (-(p[0] - a).powi(2) / (2.0 * 0.1f64.powi(2))).exp()]
    };
    let w = worst_of(for_all, vec![target(0, Direction::Max)], &f);
    let found = &w.worst[0];
    assert_eq!(found.witness[1], 1.0);
    assert!(
        found.value >= 3.0 * (1.0 - TOL) && found.value <= 3.0,
        "{found:?}"
    );
}

#[test]
fn several_metrics_share_their_runs() {
    let both = |p: &[f64]| {
        let (u, v) = uv(p);
        vec![
            narrow_peak(p),
            1.0 + (u - 0.3137).abs() + 0.5 * (v - 0.771).abs(),
        ]
    };
    let targets = vec![target(0, Direction::Max), target(1, Direction::Min)];
    let together = worst_of(box_xy(), targets, &both);
    let alone_0 = worst_of(box_xy(), vec![target(0, Direction::Max)], &|p| {
        vec![both(p)[0]]
    });
    let alone_1 = worst_of(box_xy(), vec![target(1, Direction::Min)], &|p| both(p));
    assert!(together.worst[0].value >= 10.0 * (1.0 - TOL));
    assert!(together.worst[1].value <= 1.0 + TOL);
    // The grid is run once for both metrics.
    assert!(
        together.runs < alone_0.runs + alone_1.runs,
        "{} {} {}",
        together.runs,
        alone_0.runs,
        alone_1.runs
    );
}

#[test]
fn a_failed_run_is_every_metric_s_worst_case() {
    // Runs fail (NaN) in the corner u > 0.8, v > 0.8, which the grid's corner point (1, 1) hits.
    let f = |p: &[f64]| {
        let (u, v) = uv(p);
        if u > 0.8 && v > 0.8 {
            vec![f64::NAN, f64::NAN]
        } else {
            vec![u, v]
        }
    };
    let w = worst_of(
        box_xy(),
        vec![target(0, Direction::Max), target(1, Direction::Min)],
        &f,
    );
    for found in &w.worst {
        assert!(found.failed && found.value.is_nan());
        let (u, v) = uv(&found.witness);
        assert!(u > 0.8 && v > 0.8);
    }
}

#[test]
fn a_peak_narrower_than_the_grid_behind_a_slope_is_missed() {
    // The documented blind spot: a spike of width 0.01 at u = 0.13 on a rising slope. No grid
    // point near it is a local worst case of the grid, and the grid's next worst points, which
    // take the two starts left (0.75 and 0.5), lie too far from it: no climb comes near it, and
    // the search reports the end of the slope (1), not the spike (5.13).
    let for_all = Axes::new("for_all", vec![Axis::range("u", 0.0, 1.0)]).unwrap();
    let f = |p: &[f64]| vec![p[0] + 5.0 * (-(p[0] - 0.13).powi(2) / (2.0 * 0.01f64.powi(2))).exp()];
    let w = worst_of(for_all, vec![target(0, Direction::Max)], &f);
    assert_eq!(w.worst[0].value, 1.0);
    assert_eq!(w.worst[0].witness, vec![1.0]);
}

#[test]
fn a_spike_beside_a_start_on_the_slope_is_found() {
    // The spike of width 0.01 at u = 0.37 on the same slope: the grid point 0.5, the third
    // worst, takes a start left over by the single local worst case (1); its first stencil
    // lands on the spike's flank (0.375), and the climb goes up the spike.
    let for_all = Axes::new("for_all", vec![Axis::range("u", 0.0, 1.0)]).unwrap();
    let f = |p: &[f64]| vec![p[0] + 5.0 * (-(p[0] - 0.37).powi(2) / (2.0 * 0.01f64.powi(2))).exp()];
    let w = worst_of(for_all, vec![target(0, Direction::Max)], &f);
    assert!(5.37 - w.worst[0].value < 1e-3 * 5.37, "{:?}", w.worst[0]);
}

/// A family of design points: the peak moves with the design value d.
fn moving_peak(d: &[f64], p: &[f64]) -> Vec<f64> {
    let (u, v) = uv(p);
    let a = 0.2 + 0.6 * d[0];
    vec![
        1.0 + 9.0 * (-((u - a).powi(2) + (v - 0.61).powi(2)) / (2.0 * 0.08f64.powi(2))).exp(),
        u * v,
    ]
}

fn search_designs(
    designs: &[f64],
    order: Order,
) -> (Vec<WorstCases>, Vec<Vec<cushion_design::Run>>) {
    let targets = vec![target(0, Direction::Max), target(1, Direction::Min)];
    let mut s = WorstCaseSearch::new(box_xy(), targets, 2, SearchSettings::default()).unwrap();
    let ids: Vec<usize> = designs.iter().map(|&d| s.add(vec![d])).collect();
    let batches = drive_search(&mut s, &moving_peak, order);
    (ids.iter().map(|&i| s.result(i).unwrap()).collect(), batches)
}

#[test]
fn the_answer_does_not_depend_on_batching_order_or_company() {
    let designs = [0.0, 0.25, 0.5, 0.8, 1.0];
    let (together, batches) = search_designs(&designs, Order::InOrder);
    let (reordered, batches_reordered) = search_designs(&designs, Order::ReversedChunks(7));
    assert_eq!(together, reordered);
    assert_eq!(batches, batches_reordered);
    for (k, &d) in designs.iter().enumerate() {
        // The same design point searched alone: the same runs, the same answer.
        let (alone, _) = search_designs(&[d], Order::ReversedChunks(3));
        assert_eq!(alone[0], together[k]);
        assert!(
            together[k].worst[0].value >= 10.0 * (1.0 - TOL),
            "design {d}: {:?}",
            together[k]
        );
        assert_eq!(together[k].worst[1].value, 0.0);
    }
    // One batch advances every design point's search: far fewer batches than runs.
    let runs: usize = together.iter().map(|w| w.runs).sum();
    assert!(
        batches.len() * 10 < runs,
        "{} batches for {runs} runs",
        batches.len()
    );
}

#[test]
fn the_protocol_and_bad_settings_are_refused() {
    let targets = vec![target(0, Direction::Max)];
    let bad = SearchSettings {
        grid: 1,
        ..SearchSettings::default()
    };
    let e = WorstCaseSearch::new(box_xy(), targets.clone(), 1, bad)
        .err()
        .unwrap();
    assert_eq!(
        e.to_string(),
        "search.grid = 1: at least 2 points per range"
    );
    assert!(WorstCaseSearch::new(
        box_xy(),
        vec![target(1, Direction::Max)],
        1,
        SearchSettings::default()
    )
    .is_err());
    // Four list axes of 100 values: a coarse grid of 10^8 points is refused, not allocated.
    let lists = Axes::new(
        "for_all",
        (0..4)
            .map(|i| Axis::values(&format!("k{i}"), 100))
            .collect(),
    )
    .unwrap();
    let e = WorstCaseSearch::new(lists, targets.clone(), 1, SearchSettings::default())
        .err()
        .unwrap();
    assert!(
        e.to_string()
            .starts_with("search.grid = 5: a grid of at most"),
        "{e}"
    );
    let mut s = WorstCaseSearch::new(box_xy(), targets, 1, SearchSettings::default()).unwrap();
    s.add(vec![]);
    let batch = s.ask();
    assert_eq!(batch.len(), 25);
    assert_eq!(s.ask(), batch, "asking again hands out the same batch");
    assert!(matches!(
        s.tell(vec![vec![1.0]; 24]),
        Err(DesignError::Protocol(_))
    ));
    assert!(matches!(
        s.tell(vec![vec![1.0, 2.0]; 25]),
        Err(DesignError::Protocol(_))
    ));
    assert!(s.result(0).is_none());
    s.tell(vec![vec![1.0]; 25]).unwrap();
    assert!(s.tell(vec![vec![1.0]; 25]).is_err(), "no batch is waiting");
}

#[test]
fn bad_axes_name_the_key() {
    let e = Axes::new("for_all", vec![Axis::range("mass", 1.0, 0.5)]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "mass.range = [1, 0.5]: two finite numbers with low < high"
    );
    let e = Axes::new("for_all", vec![Axis::log_range("mass", 0.0, 1.0)]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "mass.range = [0, 1]: a log scale needs low > 0"
    );
    assert!(Axes::new("for_all", vec![Axis::values("module", 0)]).is_err());
    assert!(Axes::new("for_all", vec![]).is_err());
    let twice = vec![Axis::range("m", 0.0, 1.0), Axis::values("m", 2)];
    assert_eq!(
        Axes::new("for_all", twice).unwrap_err().to_string(),
        "for_all = m: each key once"
    );
    let a = box_xy();
    assert!(a.coordinates(&[7.0, 0.5]).is_err());
    assert_eq!(a.real(&[1.0, 1.0]), vec![6.0, 1.0], "the ends exactly");
}
