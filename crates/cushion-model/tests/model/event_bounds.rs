//! The model's bounds of how far its event functions stray from their chords within a step
//! (`OdeSystem::event_chord_bound`, and `event_chord_bounds`, all at once, as the integrator
//! asks; they let it skip the interior samples of quiet steps) hold along whole runs: sampled
//! at 64 points of every step's dense output, no function strays further than its bound. At
//! the same points, each function evaluated alone (`OdeSystem::event`, what the root finder
//! calls) equals its value among all of them.

use cushion_model::model::Model;
use cushion_model::simulate::solver_options;
use cushion_model::Scene;
use cushion_ode::{Control, Direction, EventAction, OdeSystem, State, Status, Step, MAX_EVENTS};

/// The model, watched: every step without an event is checked against the bounds.
struct Watch<'a> {
    m: &'a mut Model,
    event_in_step: bool,
    checked: usize,
    worst_ratio: f64,
}

impl<const N: usize> OdeSystem<N> for Watch<'_> {
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        self.m.rhs(t, y)
    }
    fn event_count(&self) -> usize {
        OdeSystem::<N>::event_count(self.m)
    }
    fn events(&self, t: f64, y: &State<N>, g: &mut [f64]) {
        self.m.events(t, y, g)
    }
    fn event_chord_bound(&self, i: usize, t0: f64, t1: f64, dev: &State<N>) -> Option<f64> {
        self.m.event_chord_bound(i, t0, t1, dev)
    }
    fn event_chord_bounds(&self, t0: f64, t1: f64, dev: &State<N>, bounds: &mut [f64]) {
        self.m.event_chord_bounds(t0, t1, dev, bounds)
    }
    fn event_direction(&self, i: usize) -> Direction {
        OdeSystem::<N>::event_direction(self.m, i)
    }
    fn on_event(&mut self, i: usize, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        self.event_in_step = true;
        self.m.on_event(i, t, y, ctl)
    }
    fn on_time_stop(&mut self, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        self.m.on_time_stop(t, y, ctl)
    }
    fn on_step(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        // A handler inside the step may have changed the regime the functions depend on.
        if !std::mem::take(&mut self.event_in_step) {
            self.check(step);
        }
        self.m.on_step(step, ctl)
    }
}

impl Watch<'_> {
    fn check<const N: usize>(&mut self, step: &Step<'_, N>) {
        let n = OdeSystem::<N>::event_count(self.m);
        let dev = step.dense.chord_deviation();
        let (mut g0, mut g1, mut g) = ([0.0; 16], [0.0; 16], [0.0; 16]);
        self.m.events(step.t0, step.y0, &mut g0[..n]);
        self.m.events(step.t1, step.y1, &mut g1[..n]);
        let bounds: Vec<Option<f64>> = (0..n)
            .map(|i| self.m.event_chord_bound(i, step.t0, step.t1, &dev))
            .collect();
        // the integrator asks for all bounds at once: the same bounds, to the bit (NaN: none)
        let mut all = [0.0; MAX_EVENTS];
        self.m
            .event_chord_bounds(step.t0, step.t1, &dev, &mut all[..n]);
        for i in 0..n {
            assert_eq!(
                bounds[i].unwrap_or(f64::NAN).to_bits(),
                all[i].to_bits(),
                "event {i}: bound alone differs from the bound among all"
            );
        }
        for k in 1..64 {
            let theta = k as f64 / 64.0;
            let t = step.t0 + theta * (step.t1 - step.t0);
            let y = step.at(t);
            self.m.events(t, &y, &mut g[..n]);
            for i in 0..n {
                // the root finder's one-function evaluation is the same function, to the bit
                assert_eq!(
                    self.m.event(i, t, &y).to_bits(),
                    g[i].to_bits(),
                    "event {i} alone differs at t = {t}"
                );
                if let Some(b) = bounds[i] {
                    let chord = g0[i] + theta * (g1[i] - g0[i]);
                    let d = (g[i] - chord).abs();
                    let scale = g0[i].abs().max(g1[i].abs());
                    assert!(
                        d <= b + 1e-12 * scale,
                        "event {i} strays {d:e} > bound {b:e} at t = {t} (step {} .. {})",
                        step.t0,
                        step.t1
                    );
                    if b > 1e-12 {
                        self.worst_ratio = self.worst_ratio.max(d / b);
                    }
                }
            }
        }
        self.checked += 1;
    }
}

fn watch<const N: usize>(scene: &Scene) -> (usize, f64) {
    let mut m = Model::new(scene);
    let y0 = State::<N>::from_column_slice(&m.y0);
    let opts = solver_options(scene);
    let mut w = Watch {
        m: &mut m,
        event_in_step: false,
        checked: 0,
        worst_ratio: 0.0,
    };
    let sol = cushion_ode::solve(&mut w, 0.0, y0, scene.t_end, &opts);
    assert!(
        matches!(sol.status, Status::Success | Status::StoppedByEvent),
        "{:?} {}",
        sol.status,
        sol.message
    );
    (w.checked, w.worst_ratio)
}

#[test]
fn event_functions_stay_within_their_chord_bounds_along_runs() {
    let variants: &[&[(&str, &str)]] = &[
        &[],
        &[("module", "bistable")],
        &[("module", "rigid")],
        &[("robot.dead_time", "0.01"), ("robot.start", "rest")],
        &[
            ("tool.dry_friction", "0.3"),
            ("object.plane_friction", "0.4"),
        ],
        &[("module", "bistable"), ("tool.dry_friction", "0.3")],
        &[("hydraulic.gas_pressure", "1e5"), ("object.mass", "1.0")],
        &[("module", "rigid"), ("object.plane_friction", "0.4")],
        &[
            ("energy.ledger", "false"),
            ("robot.brake_deceleration", "30"),
        ],
    ];
    let mut worst = 0.0f64;
    for v in variants {
        let mut scene = Scene::default();
        for (k, val) in *v {
            scene.set_from_str(k, val).unwrap();
        }
        let n = cushion_model::model::Layout::of(&scene).n;
        let (checked, ratio) = match n {
            2 => watch::<2>(&scene),
            3 => watch::<3>(&scene),
            4 => watch::<4>(&scene),
            5 => watch::<5>(&scene),
            6 => watch::<6>(&scene),
            7 => watch::<7>(&scene),
            8 => watch::<8>(&scene),
            9 => watch::<9>(&scene),
            10 => watch::<10>(&scene),
            _ => panic!("{n} states"),
        };
        assert!(checked > 20, "{v:?}: {checked} steps checked");
        worst = worst.max(ratio);
    }
    // the bounds are not vacuous: somewhere a function comes within a factor of a few of one
    assert!(worst > 0.1, "bounds far looser than needed: {worst}");
}
