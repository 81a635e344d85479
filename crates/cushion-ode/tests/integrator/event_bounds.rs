//! The cheaper event scan: a system that bounds how far its event functions stray from their
//! chords lets quiet steps skip the interior samples; the bound must never change a result.

use std::cell::Cell;

use cushion_ode::test_models::arenstorf::{initial_state, Arenstorf, PERIOD};
use cushion_ode::{solve, Control, EventAction, OdeSystem, SolverOptions, State, Status, Step};

/// Checks on every step that the dense output stays within `chord_deviation` of its chord,
/// and keeps the largest ratio of the actual straying to the bound.
struct ChordWatch {
    inner: Arenstorf,
    worst_ratio: f64,
    steps: usize,
}

impl OdeSystem<4> for ChordWatch {
    fn rhs(&self, t: f64, y: &State<4>) -> State<4> {
        self.inner.rhs(t, y)
    }
    fn on_step(&mut self, step: &Step<'_, 4>, _ctl: &mut Control) {
        let bound = step.dense.chord_deviation();
        let mut worst = [0.0f64; 4];
        for k in 1..200 {
            let theta = k as f64 / 200.0;
            let t = step.t0 + theta * (step.t1 - step.t0);
            let y = step.at(t);
            let chord = step.y0 + (step.y1 - step.y0) * theta;
            for j in 0..4 {
                let d = (y[j] - chord[j]).abs();
                assert!(
                    d <= bound[j] * (1.0 + 1e-12) + 1e-300,
                    "component {j} strays {d:e} > bound {:e} at theta {theta}",
                    bound[j]
                );
                worst[j] = worst[j].max(d);
            }
        }
        for j in 0..4 {
            if bound[j] > 0.0 {
                self.worst_ratio = self.worst_ratio.max(worst[j] / bound[j]);
            }
        }
        self.steps += 1;
    }
}

#[test]
fn chord_deviation_bounds_the_dense_output_and_is_not_loose() {
    let mut sys = ChordWatch {
        inner: Arenstorf,
        worst_ratio: 0.0,
        steps: 0,
    };
    let opts = SolverOptions {
        rtol: 1e-6.into(),
        atol: 1e-6.into(),
        ..Default::default()
    };
    let sol = solve(&mut sys, 0.0, initial_state(), PERIOD, &opts);
    assert_eq!(sol.status, Status::Success);
    assert!(sys.steps > 50);
    // |theta (1-theta)| <= 1/4 is reached at theta = 1/2, and the bracket is often dominated
    // by r3: the bound is within a factor of a few of the real straying.
    assert!(
        sys.worst_ratio > 0.5,
        "bound too loose: {}",
        sys.worst_ratio
    );
}

/// Free flight `x' = v, v' = -1` under a ceiling at `x = c`: `g = c - x`, affine in the state,
/// so it strays from its chord exactly as `x` does. Counts the evaluations of `g`.
struct Ceiling {
    c: f64,
    with_bound: bool,
    evaluations: Cell<usize>,
    hits: usize,
}

impl OdeSystem<2> for Ceiling {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(y[1], -1.0)
    }
    fn event_count(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &State<2>, g: &mut [f64]) {
        self.evaluations.set(self.evaluations.get() + 1);
        g[0] = self.c - y[0];
    }
    fn event_chord_bound(
        &self,
        _i: usize,
        _t0: f64,
        _t1: f64,
        deviation: &State<2>,
    ) -> Option<f64> {
        self.with_bound.then_some(deviation[0])
    }
    fn on_event(
        &mut self,
        _i: usize,
        _t: f64,
        _y: &mut State<2>,
        _ctl: &mut Control,
    ) -> EventAction {
        self.hits += 1;
        EventAction::Continue
    }
}

fn fly(c: f64, with_bound: bool) -> (cushion_ode::Solution<2>, usize, usize) {
    let mut sys = Ceiling {
        c,
        with_bound,
        evaluations: Cell::new(0),
        hits: 0,
    };
    // x = t - t^2/2 on [0, 2]: a parabola that DOPRI5 integrates exactly, in one step.
    let opts = SolverOptions {
        h0: Some(2.0),
        ..Default::default()
    };
    let sol = solve(&mut sys, 0.0, State::<2>::new(0.0, 1.0), 2.0, &opts);
    assert_eq!(sol.status, Status::Success);
    assert_eq!(sol.stats.steps, 1);
    (sol, sys.evaluations.get(), sys.hits)
}

#[test]
fn a_step_far_from_every_event_is_not_sampled_inside() {
    // Ceiling at 10: g = 10 at both ends and strays at most 0.5 + looseness, far below 10.
    let (_, with, hits) = fly(10.0, true);
    let (_, without, _) = fly(10.0, false);
    assert_eq!(hits, 0);
    assert_eq!(with, 2, "only the two ends");
    assert_eq!(without, 2 + 4, "the ends and the four interior samples");
}

#[test]
fn two_crossings_inside_one_step_are_still_found_with_a_bound() {
    // Ceiling at 0.45 below the apex 0.5: g = 0.45 at both ends, yet it crosses at
    // t = 1 -+ sqrt(0.1). The bound (>= 0.5) does not exclude it, so the step is sampled.
    let exact = [1.0 - 0.1f64.sqrt(), 1.0 + 0.1f64.sqrt()];
    for with_bound in [true, false] {
        let (sol, _, hits) = fly(0.45, with_bound);
        assert_eq!(hits, 2);
        for (e, x) in sol.events.iter().zip(exact) {
            assert!((e.t - x).abs() < 1e-12, "{} vs {x}", e.t);
        }
    }
}
