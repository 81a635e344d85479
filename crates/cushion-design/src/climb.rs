//! One local refinement of a worst case: a compass search in the normalised `for_all` box.
//!
//! From its start it polls the two neighbours at distance `step` along every range (clipped to
//! the box; list axes stay put, their values being unordered). If a neighbour is worse (a larger
//! badness) the search moves there and keeps its step; otherwise the centre is the worst of its
//! stencil, and the search estimates how much worse the true worst case near it can be: along
//! each range `|b(c + h) - b(c - h)| / 2`, summed over the ranges. For a smooth peak
//! (`b* - k (x - a)^2`, `|a - c| <= h/2`) that bounds the gain `k (a - c)^2` by `2 k h |a - c|`;
//! for a kink (`b* - k |x - a|`) it equals the gain `k |a - c|`. When the estimate is within
//! `tolerance` of the centre's badness (relative), and the step has been halved at least
//! [`PROBE_HALVINGS`] times, the search stops; else it halves the step, down to `min_step`. The
//! forced halving probes between the centre and its first neighbours: a peak narrower than the
//! first step that sits between two lower points shows no gain at the first step (the object's
//! final speed at a strong gas preload peaks at 0.1 kg, between the coarse grid's 0.05 and
//! 0.29 kg; guarded by `tests::probes_a_narrow_peak_beside_its_start`). A centre on the edge of
//! the box with one neighbour along a range counts no gain along it: the worst case there is
//! the edge (a ridge along the edge of the box).
//!
//! Two more rules, each for a way a compass search stops short:
//! - **A start that is not a local worst case of the grid** polls its first stencil at `step`
//!   and at `step / 2` and moves to the worst of them: its better neighbour one step away may
//!   lie beyond a narrow peak beside it (at a 5.5 kPa gas preload the object's final speed
//!   peaks at 0.074 kg, between the grid's 0.05 kg and the 0.17 kg on the peak's far side where
//!   the first step lands; guarded by
//!   `tests::a_start_off_the_grid_peaks_polls_half_its_first_step`).
//! - **The faces, once.** Where the climb would stop, it polls once, along every range, the two
//!   points on the faces of the box through its centre, and goes on from the worst, with its
//!   first step again, if that is as bad as the centre to within the tolerance (a plateau's
//!   values differ by the solver's noise). The worst case of an impact often lies on a plateau
//!   that ends at a face: once the object has left, a longer dead time changes nothing, and a
//!   ridge that rises towards that face is too steep for the stencil to follow (the bistable
//!   module at 0.75 m/s; guarded by `tests::a_plateau_is_followed_to_its_face`).

/// Normalised coordinates in the `for_all` box.
pub(crate) type Coord = Vec<f64>;

/// Halvings of the first step (half the coarse grid's spacing) before the gain estimate may stop
/// a climb. One probes at a quarter of the grid's spacing: against brute force on the 1/64
/// design lattice (`lab/design_vs_brute.py`) it removed every shortfall over 2e-3 for 1.3 times
/// the runs; also polling the diagonals of every pair of ranges cost 3.4 times the runs.
pub(crate) const PROBE_HALVINGS: usize = 1;

/// The settings a climb reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rules {
    pub(crate) tolerance: f64,
    pub(crate) min_step: f64,
    pub(crate) max_polls: usize,
    /// Halvings of the step before the gain estimate may stop the climb.
    pub(crate) probe_halvings: usize,
}

/// Where a climb stands between stencils.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Polling stencils at `step` (the first also at `step / 2` when `half_first` is set).
    Stencils,
    /// The climb would stop: poll the faces through the centre once.
    Faces,
    /// The faces were polled; the next stop is final.
    FacesDone,
}

/// The points a climb polls in one go: pairs along each range (at `-h` and `+h`, if inside),
/// with `h` either the step or half of it, or the faces through the centre.
#[derive(Clone, Debug)]
struct Stencil {
    /// (step of the pair, its two points).
    pairs: Vec<(f64, [Option<Coord>; 2])>,
}

/// One compass search for one target.
#[derive(Clone, Debug)]
pub(crate) struct Climb {
    pub(crate) target: usize,
    pub(crate) center: Coord,
    center_badness: f64,
    pub(crate) step: f64,
    /// The step it started with, which it takes up again after a move to a face.
    first_step: f64,
    polls: usize,
    halvings: usize,
    /// Whether the first stencil also polls at half the step (a start that is not a local
    /// worst case of the grid).
    half_first: bool,
    phase: Phase,
    poll: Option<Stencil>,
    pub(crate) done: bool,
}

/// `center` moved to `x` along range `i`, unless that is where it is.
fn moved(center: &Coord, i: usize, x: f64) -> Option<Coord> {
    (x != center[i]).then(|| {
        let mut p = center.clone();
        p[i] = x;
        p
    })
}

impl Climb {
    /// A climb from a local worst case of the grid.
    pub(crate) fn new(target: usize, center: Coord, center_badness: f64, step: f64) -> Climb {
        Climb {
            target,
            center,
            center_badness,
            step,
            first_step: step,
            polls: 0,
            halvings: 0,
            half_first: false,
            phase: Phase::Stencils,
            poll: None,
            done: false,
        }
    }

    /// A climb from a grid point that is not a local worst case: its first stencil polls at
    /// half the step too.
    pub(crate) fn from_slope(
        target: usize,
        center: Coord,
        center_badness: f64,
        step: f64,
    ) -> Climb {
        Climb {
            half_first: true,
            ..Climb::new(target, center, center_badness, step)
        }
    }

    /// The points of the current stencil, building it if needed.
    pub(crate) fn poll(&mut self, continuous: &[bool]) -> Vec<Coord> {
        let (center, step) = (&self.center, self.step);
        let (faces, half) = (self.phase == Phase::Faces, self.polls_half_step_next());
        let stencil = self.poll.get_or_insert_with(|| {
            let mut pairs = Vec::new();
            for (i, _) in continuous.iter().enumerate().filter(|(_, &c)| c) {
                if faces {
                    pairs.push((1.0, [moved(center, i, 0.0), moved(center, i, 1.0)]));
                    continue;
                }
                let scales: &[f64] = if half { &[1.0, 0.5] } else { &[1.0] };
                for &scale in scales {
                    let h = step * scale;
                    let side = |sign: f64| moved(center, i, (center[i] + sign * h).clamp(0.0, 1.0));
                    pairs.push((h, [side(-1.0), side(1.0)]));
                }
            }
            Stencil { pairs }
        });
        stencil
            .pairs
            .iter()
            .flat_map(|(_, pts)| pts.iter().flatten().cloned())
            .collect()
    }

    /// Decide on the polled stencil, given every point's badness: move, halve the step, poll
    /// the faces or stop.
    pub(crate) fn decide(&mut self, badness: impl Fn(&Coord) -> f64, rules: &Rules) {
        let Some(stencil) = self.poll.take() else {
            return;
        };
        self.polls += 1;
        let mut best: Option<(f64, &Coord, f64)> = None;
        let mut gain = 0.0;
        for (h, pts) in &stencil.pairs {
            let b: Vec<Option<f64>> = pts.iter().map(|p| p.as_ref().map(&badness)).collect();
            for (p, b) in pts.iter().zip(&b) {
                if let (Some(p), Some(b)) = (p, b) {
                    if best.is_none_or(|(bb, _, _)| *b > bb) {
                        best = Some((*b, p, *h));
                    }
                }
            }
            if let [Some(lo), Some(hi)] = b[..] {
                if *h == self.step {
                    gain += (hi - lo).abs() / 2.0;
                }
            }
        }
        let faces = self.phase == Phase::Faces;
        if faces {
            self.phase = Phase::FacesDone;
        }
        match best {
            // A face as bad as the centre to within the tolerance is taken: along a plateau the
            // climb goes on from the face, where the ridge that rises towards it ends. The worst
            // case found so far is kept by the point search, whatever the centre.
            Some((b, p, _))
                if faces
                    && b >= self.center_badness - rules.tolerance * self.center_badness.abs() =>
            {
                self.center = p.clone();
                self.center_badness = b;
                self.step = self.first_step;
                self.halvings = 0;
            }
            Some((b, p, h)) if !faces && b > self.center_badness => {
                self.center = p.clone();
                self.center_badness = b;
                if h < self.step {
                    self.step = h;
                    self.halvings += 1;
                }
            }
            _ if faces => self.done = true,
            _ => {
                let close = gain <= rules.tolerance * self.center_badness.abs()
                    && self.halvings >= rules.probe_halvings;
                if close || self.step / 2.0 < rules.min_step {
                    self.stop();
                } else {
                    self.step /= 2.0;
                    self.halvings += 1;
                }
            }
        }
        if self.polls >= rules.max_polls {
            self.done = true;
        }
    }

    /// Whether the next stencil also polls at half the step: the first of a start off the
    /// grid's local worst cases.
    fn polls_half_step_next(&self) -> bool {
        self.half_first && self.polls == 0
    }

    /// Where the climb would stop: poll the faces first, the first time.
    fn stop(&mut self) {
        match self.phase {
            Phase::Stencils => self.phase = Phase::Faces,
            _ => self.done = true,
        }
    }

    /// Whether two climbs would poll the same stencils from now on.
    pub(crate) fn same_as(&self, other: &Climb) -> bool {
        self.target == other.target
            && self.center == other.center
            && self.step == other.step
            && self.halvings == other.halvings
            && self.phase == other.phase
            && self.polls_half_step_next() == other.polls_half_step_next()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULES: Rules = Rules {
        tolerance: 1e-6,
        min_step: 1e-9,
        max_polls: 200,
        probe_halvings: 0,
    };

    /// Drive one climb on a function of the normalised coordinates.
    fn climb(f: impl Fn(&Coord) -> f64, start: Coord, step: f64) -> (Climb, usize) {
        let mut c = Climb::new(0, start.clone(), f(&start), step);
        let mut evaluations = 0;
        while !c.done {
            evaluations += c.poll(&[true, true]).len();
            c.decide(&f, &RULES);
        }
        (c, evaluations)
    }

    #[test]
    fn climbs_a_smooth_peak_and_a_kink_to_the_tolerance() {
        let smooth = |p: &Coord| 5.0 - 3.0 * (p[0] - 0.3137).powi(2) - (p[1] - 0.771).powi(2);
        let (c, n) = climb(smooth, vec![0.25, 0.75], 0.125);
        assert!(5.0 - smooth(&c.center) < 5.0 * 1e-6, "{:?}", c.center);
        assert!(n < 200, "{n} evaluations");
        let kink = |p: &Coord| 2.0 - (p[0] - 0.3137).abs() - 0.5 * (p[1] - 0.771).abs();
        let (c, _) = climb(kink, vec![0.5, 0.5], 0.125);
        assert!(2.0 - kink(&c.center) <= 2.0 * 1e-6, "{:?}", c.center);
    }

    #[test]
    fn probes_a_narrow_peak_beside_its_start() {
        // A start on the edge x = 0 whose first neighbour (x = 0.125) is lower, with a narrow
        // peak between them at x = 0.06: flat in y, so no stencil shows a gain at the first step.
        let peak = |p: &Coord| 1.0 + 0.02 * (-((p[0] - 0.06) / 0.03).powi(2)).exp() - 0.1 * p[0];
        let start = vec![0.0, 0.5];
        let mut without = Climb::new(0, start.clone(), peak(&start), 0.125);
        let mut with = without.clone();
        let probing = Rules {
            probe_halvings: 1,
            ..RULES
        };
        for (c, rules) in [(&mut without, &RULES), (&mut with, &probing)] {
            while !c.done {
                c.poll(&[true, true]);
                c.decide(peak, rules);
            }
        }
        assert_eq!(
            without.center[0], start[0],
            "without a probe the climb stops at its start's x"
        );
        let best = 1.0 + 0.02 - 0.1 * 0.06;
        assert!(best - peak(&with.center) < 1e-6 * best, "{:?}", with.center);
    }

    #[test]
    fn stops_on_the_edge_of_the_box() {
        // Worst on the edge x = 1, at y = 0.4.
        let ridge = |p: &Coord| p[0] - (p[1] - 0.4).powi(2);
        let (c, _) = climb(ridge, vec![0.75, 0.5], 0.125);
        assert_eq!(c.center[0], 1.0);
        assert!((c.center[1] - 0.4).abs() < 2e-3, "{:?}", c.center);
    }

    /// Drive a climb to its end; the evaluations it asked for.
    fn run(c: &mut Climb, f: impl Fn(&Coord) -> f64) -> usize {
        let mut evaluations = 0;
        while !c.done {
            evaluations += c.poll(&[true, true]).len();
            c.decide(&f, &RULES);
        }
        evaluations
    }

    #[test]
    fn a_start_off_the_grid_peaks_polls_half_its_first_step() {
        // A broad peak (0.9 at x = 0.3) and a narrow higher one (1.0 at x = 0.06) beside the
        // start x = 0, whose first neighbour (x = 0.125) lies beyond the narrow one and is worse
        // than the start: a plain climb walks on to the broad peak.
        let f = |p: &Coord| (0.9 - 0.4 * (p[0] - 0.3).abs()).max(1.0 - 3.0 * (p[0] - 0.06).abs());
        let start = vec![0.0, 0.5];
        let mut plain = Climb::new(0, start.clone(), f(&start), 0.125);
        run(&mut plain, f);
        assert!((f(&plain.center) - 0.9).abs() < 1e-5, "{:?}", plain.center);
        let mut half = Climb::from_slope(0, start.clone(), f(&start), 0.125);
        run(&mut half, f);
        assert!(1.0 - f(&half.center) < 1e-5, "{:?}", half.center);
    }

    #[test]
    fn a_plateau_is_followed_to_its_face() {
        // A plateau rising slowly with x where y >= 0.5 + 5 x, falling off steeply below it,
        // and a cliff at x = 0.1: the worst case, 1.01, is at (0.1, 1), on the face y = 1. The
        // compass stencil stalls at the plateau's edge, where a step in x falls off it.
        let f = |p: &Coord| {
            let (x, y) = (p[0], p[1]);
            if x > 0.1 {
                return 0.5;
            }
            1.0 + 0.1 * x - (0.5 + 5.0 * x - y).max(0.0)
        };
        let start = vec![0.05, 0.76];
        let mut c = Climb::new(0, start.clone(), f(&start), 0.125);
        run(&mut c, f);
        assert_eq!(c.center[1], 1.0, "{:?}", c.center);
        assert!(1.01 - f(&c.center) < 1e-5, "{:?}", c.center);
    }
}
