//! The refinement of the design space on feasible regions known in closed form (a disc, a
//! half-plane cut by a second limit): every design cell whose true margin exceeds 1 % is
//! classified right, the runs spent are a small fraction of a brute-force grid's, the best
//! design is where it should be, and the answer does not depend on how batches are evaluated.

use crate::common::{drive_refinement, Order};
use cushion_design::{
    Axes, Axis, DesignError, Limit, Limits, Objective, RefineSettings, Refinement, Sense,
};

/// The brute force the issue compares with: a 64 x 64 design grid, 21 x 21 `for_all` grid.
const BRUTE_FORCE_RUNS: usize = 64 * 64 * 21 * 21;

fn unit_box(keys: &[&str]) -> Axes {
    Axes::new(
        "box",
        keys.iter().map(|k| Axis::range(k, 0.0, 1.0)).collect(),
    )
    .unwrap()
}

/// The disc: the metric is r^2 (1 + 0.2 sin(pi t) (1 + 0.1 s)) around (0.5, 0.45), worst at
/// t = 0.5, s = 1 (factor 1.22); the limit 1.22 * 0.09 makes the feasible region the disc of
/// radius 0.3, with true margin 1 - r^2 / 0.09.
fn disc_model(d: &[f64], p: &[f64]) -> Vec<f64> {
    let r2 = (d[0] - 0.5).powi(2) + (d[1] - 0.45).powi(2);
    let factor = 1.0 + 0.2 * (std::f64::consts::PI * p[0]).sin() * (1.0 + 0.1 * p[1]);
    let cost = ((d[0] - 0.9).powi(2) + (d[1] - 0.9).powi(2)) * (1.0 + 0.01 * p[0]);
    vec![r2 * factor, cost]
}

/// The true margin: the disc's, or the cost's (always over 99.8 %) if smaller.
fn disc_margin(x: f64, y: f64) -> f64 {
    let disc = 1.0 - ((x - 0.5).powi(2) + (y - 0.45).powi(2)) / 0.09;
    let cost = 1.0 - ((x - 0.9).powi(2) + (y - 0.9).powi(2)) * 1.01 / 1000.0;
    disc.min(cost)
}

fn disc_map(objective: Option<Objective>) -> (Refinement, usize) {
    let limits = Limits::new(
        vec![Limit::max("force", 1.22 * 0.09), Limit::max("cost", 1000.0)],
        objective,
    )
    .unwrap();
    let mut map = Refinement::new(
        unit_box(&["x", "y"]),
        unit_box(&["t", "s"]),
        limits,
        RefineSettings::default(),
    )
    .unwrap();
    let (runs, _) = drive_refinement(&mut map, &disc_model, Order::InOrder);
    assert_eq!(runs, map.runs());
    assert_eq!(runs, map.points().iter().map(|p| p.runs).sum::<usize>());
    (map, runs)
}

/// Cells of a 64 x 64 design grid (their centres) whose true margin exceeds 1 %: how many, and
/// how many the map gets wrong.
fn misclassified(
    map: &Refinement,
    margin: impl Fn(&[f64]) -> f64,
    extra: &[f64],
) -> (usize, usize) {
    let (mut judged, mut wrong) = (0, 0);
    for i in 0..64 {
        for j in 0..64 {
            let mut p = vec![(i as f64 + 0.5) / 64.0, (j as f64 + 0.5) / 64.0];
            p.extend_from_slice(extra);
            let m = margin(&p);
            if m.abs() > 0.01 {
                judged += 1;
                if map.classify(&p).unwrap() != (m >= 0.0) {
                    wrong += 1;
                }
            }
        }
    }
    (judged, wrong)
}

#[test]
fn the_disc_is_mapped_right_at_a_small_fraction_of_the_runs() {
    let (map, runs) = disc_map(None);
    let (judged, wrong) = misclassified(&map, |p| disc_margin(p[0], p[1]), &[]);
    assert!(judged > 3900, "{judged}");
    assert_eq!(wrong, 0);
    assert!(
        runs * 20 < BRUTE_FORCE_RUNS,
        "{runs} runs: over 5 % of the brute force"
    );
    // Every judged point's margin is within the search tolerance of the truth (the worst
    // case found lies at most 0.1 % under the true one, so the margin at most that above it).
    for p in map.points() {
        let truth = disc_margin(p.design[0], p.design[1]);
        // A worst case w under its limit L by at most 0.1 % of w moves the margin by 0.1 % of w / L.
        let slack = 1e-3 * (1.0 - truth).max(0.0) + 1e-12;
        assert!(
            p.margin >= truth - 1e-12 && p.margin <= truth + slack,
            "{p:?}: {truth}"
        );
    }
    // Without an objective the best design has the largest margin: the lattice point nearest
    // the centre, to the resolution.
    let best = map.best().unwrap();
    assert!(best.feasible);
    let r = ((best.design[0] - 0.5).powi(2) + (best.design[1] - 0.45).powi(2)).sqrt();
    assert!(r <= 1.0 / 64.0, "{best:?}");
}

#[test]
fn the_objective_picks_the_feasible_point_nearest_its_optimum() {
    let minimize = Objective {
        metric: "cost".into(),
        sense: Sense::Minimize,
    };
    let (map, _) = disc_map(Some(minimize));
    let best = map.best().unwrap();
    assert!(best.feasible);
    // The point of the disc nearest (0.9, 0.9): the centre plus 0.3 towards it.
    let (dx, dy) = (0.4, 0.45);
    let n = f64::hypot(dx, dy);
    let (ox, oy) = (0.5 + 0.3 * dx / n, 0.45 + 0.3 * dy / n);
    let off = f64::hypot(best.design[0] - ox, best.design[1] - oy);
    assert!(off < 2.0 / 64.0, "{best:?} is {off} from ({ox}, {oy})");
    // Its objective is the worst cost over the box (at t = 1), to the tolerance.
    let cost = ((best.design[0] - 0.9).powi(2) + (best.design[1] - 0.9).powi(2)) * 1.01;
    let found = best.objective.unwrap();
    assert!(
        found <= cost && found >= cost * (1.0 - 1e-3),
        "{found} vs {cost}"
    );
}

/// A half-plane cut by a second limit, over a log design axis and a list design axis
/// (`module`): speed 1.2 (x + v/2) + 0.3 module <= 0.96, where v is y's place on its log scale,
/// and clearance 1 - x (1/2 + t/2) >= 0.25, i.e. x <= 0.75.
fn plane_model(d: &[f64], p: &[f64]) -> Vec<f64> {
    let v = (d[1] / 1.0).ln() / 100f64.ln();
    let speed = (d[0] + 0.5 * v) * (1.0 + 0.1 * p[1] * p[0]) + 0.3 * d[2];
    vec![speed, 1.0 - d[0] * (0.5 + 0.5 * p[0])]
}

fn plane_margin(p: &[f64]) -> f64 {
    let v = p[1].ln() / 100f64.ln();
    let speed = 1.2 * (p[0] + 0.5 * v) + 0.3 * p[2];
    f64::min((0.96 - speed) / 0.96, (1.0 - p[0] - 0.25) / 0.25)
}

fn plane_map(order: Order) -> Refinement {
    let design = Axes::new(
        "design",
        vec![
            Axis::range("x", 0.0, 1.0),
            Axis::log_range("y", 1.0, 100.0),
            Axis::values("module", 2),
        ],
    )
    .unwrap();
    let for_all = Axes::new(
        "for_all",
        vec![Axis::range("t", 0.0, 1.0), Axis::values("k", 3)],
    )
    .unwrap();
    let limits = Limits::new(
        vec![Limit::max("speed", 0.96), Limit::min("clearance", 0.25)],
        None,
    )
    .unwrap();
    let mut map = Refinement::new(design, for_all, limits, RefineSettings::default()).unwrap();
    drive_refinement(&mut map, &plane_model, order);
    map
}

#[test]
fn a_half_plane_with_a_log_axis_and_a_list_axis_is_mapped_right() {
    let map = plane_map(Order::InOrder);
    for module in [0.0, 1.0] {
        // The 64 x 64 grid over (x, v), mapped to y on its log scale.
        let margin = |p: &[f64]| plane_margin(&[p[0], 100f64.powf(p[1]), p[2]]);
        let (mut judged, mut wrong) = (0, 0);
        for i in 0..64 {
            for j in 0..64 {
                let (x, v) = ((i as f64 + 0.5) / 64.0, (j as f64 + 0.5) / 64.0);
                let m = margin(&[x, v, module]);
                if m.abs() > 0.01 {
                    judged += 1;
                    wrong += usize::from(
                        map.classify(&[x, 100f64.powf(v), module]).unwrap() != (m >= 0.0),
                    );
                }
            }
        }
        assert!(judged > 3800, "{judged}");
        assert_eq!(wrong, 0, "module {module}");
    }
    // Brute force here: 2 x 64 x 64 designs, 21 x 3 for_all runs each.
    let brute = 2 * 64 * 64 * 21 * 3;
    assert!(map.runs() * 10 < brute, "{} runs of {brute}", map.runs());
    // The best design (largest margin) is in the corner x = 0, y = 1 of module 0, where
    // speed 0 is 100 % under its limit and clearance 1 is 300 % over: margin 1.
    let best = map.best().unwrap();
    assert_eq!(best.design, vec![0.0, 1.0, 0.0]);
    assert!((best.margin - 1.0).abs() < 1e-12);
}

#[test]
fn the_map_does_not_depend_on_how_batches_are_evaluated() {
    let a = plane_map(Order::InOrder);
    let b = plane_map(Order::ReversedChunks(7));
    assert_eq!(a.points(), b.points());
    assert_eq!(a.cells(), b.cells());
    assert_eq!(a.runs(), b.runs());
}

#[test]
fn failed_runs_make_a_design_infeasible() {
    // One design range: x <= 0.5 meets the limit; beyond x = 0.8 some runs fail.
    let model = |d: &[f64], p: &[f64]| {
        if d[0] > 0.8 && p[0] > 0.5 {
            vec![f64::NAN]
        } else {
            vec![d[0] * (1.0 + 0.1 * p[0])]
        }
    };
    let limits = Limits::new(vec![Limit::max("force", 0.55)], None).unwrap();
    let mut map = Refinement::new(
        unit_box(&["x"]),
        unit_box(&["t"]),
        limits,
        RefineSettings::default(),
    )
    .unwrap();
    drive_refinement(&mut map, &model, Order::InOrder);
    assert!(map.classify(&[0.3]).unwrap());
    assert!(!map.classify(&[0.6]).unwrap());
    assert!(!map.classify(&[0.9]).unwrap());
    let failed = map.points().iter().find(|p| p.design[0] == 1.0).unwrap();
    assert!(!failed.feasible && failed.margin == f64::NEG_INFINITY);
    assert!(failed.worst[0].failed && failed.worst[0].witness[0] > 0.5);
    // The boundary x = 0.5 is found to the resolution.
    let edge = map
        .points()
        .iter()
        .filter(|p| p.feasible)
        .map(|p| p.design[0])
        .fold(0.0, f64::max);
    assert_eq!(edge, 0.5);
}

#[test]
fn bad_questions_are_refused() {
    let limits = || Limits::new(vec![Limit::max("force", 1.0)], None).unwrap();
    let five = unit_box(&["a", "b", "c", "d", "e"]);
    let e = Refinement::new(five, unit_box(&["t"]), limits(), RefineSettings::default())
        .err()
        .unwrap();
    assert_eq!(e.to_string(), "design = 5 axes: 1 to 4 axes");
    let e = Refinement::new(
        unit_box(&["t"]),
        unit_box(&["t"]),
        limits(),
        RefineSettings::default(),
    )
    .err()
    .unwrap();
    assert_eq!(
        e.to_string(),
        "t = in design and in for_all: a key in one of them"
    );
    let coarse = RefineSettings {
        resolution: 0.0,
        ..RefineSettings::default()
    };
    assert!(Refinement::new(unit_box(&["x"]), unit_box(&["t"]), limits(), coarse).is_err());
    let mut map = Refinement::new(
        unit_box(&["x"]),
        unit_box(&["t"]),
        limits(),
        RefineSettings::default(),
    )
    .unwrap();
    assert!(matches!(
        map.classify(&[0.5]),
        Err(DesignError::Protocol(_))
    ));
    drive_refinement(&mut map, &|d, _| vec![d[0]], Order::InOrder);
    assert!(matches!(
        map.classify(&[1.5]),
        Err(DesignError::Config { .. })
    ));
    assert!(map.classify(&[1.0]).unwrap());
}

#[test]
fn lists_only_are_taken_value_by_value() {
    // Three modules, four conditions: worst case module + 3, limit 4.
    let design = Axes::new("design", vec![Axis::values("module", 3)]).unwrap();
    let for_all = Axes::new("for_all", vec![Axis::values("k", 4)]).unwrap();
    let limits = Limits::new(vec![Limit::max("force", 4.0)], None).unwrap();
    let mut map = Refinement::new(design, for_all, limits, RefineSettings::default()).unwrap();
    let (runs, batches) = drive_refinement(&mut map, &|d, p| vec![d[0] + p[0]], Order::InOrder);
    assert_eq!((runs, batches), (12, 1), "every pair once, in one batch");
    let feasible: Vec<bool> = (0..3).map(|m| map.classify(&[m as f64]).unwrap()).collect();
    assert_eq!(feasible, [true, true, false]);
    assert_eq!(map.points()[1].margin, 0.0);
    assert_eq!(map.points()[2].worst[0].witness, vec![3.0]);
    assert_eq!(map.best().unwrap().design, vec![0.0]);
    assert!(map.classify(&[0.5]).is_err(), "not a value's index");
}
