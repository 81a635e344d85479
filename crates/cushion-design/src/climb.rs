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

/// One compass search for one target.
#[derive(Clone, Debug)]
pub(crate) struct Climb {
    pub(crate) target: usize,
    pub(crate) center: Coord,
    center_badness: f64,
    pub(crate) step: f64,
    polls: usize,
    halvings: usize,
    /// The stencil being polled: (range axis, its points at -step and +step, if inside).
    poll: Option<Vec<(usize, [Option<Coord>; 2])>>,
    pub(crate) done: bool,
}

impl Climb {
    pub(crate) fn new(target: usize, center: Coord, center_badness: f64, step: f64) -> Climb {
        Climb {
            target,
            center,
            center_badness,
            step,
            polls: 0,
            halvings: 0,
            poll: None,
            done: false,
        }
    }

    /// The points of the current stencil, building it if needed.
    pub(crate) fn poll(&mut self, continuous: &[bool]) -> Vec<Coord> {
        let (center, step) = (&self.center, self.step);
        let stencil = self.poll.get_or_insert_with(|| {
            let mut s = Vec::new();
            for (i, _) in continuous.iter().enumerate().filter(|(_, &c)| c) {
                let side = |sign: f64| {
                    let x = (center[i] + sign * step).clamp(0.0, 1.0);
                    (x != center[i]).then(|| {
                        let mut p = center.clone();
                        p[i] = x;
                        p
                    })
                };
                s.push((i, [side(-1.0), side(1.0)]));
            }
            s
        });
        stencil
            .iter()
            .flat_map(|(_, pts)| pts.iter().flatten().cloned())
            .collect()
    }

    /// Decide on the polled stencil, given every point's badness: move, halve the step or stop.
    pub(crate) fn decide(&mut self, badness: impl Fn(&Coord) -> f64, rules: &Rules) {
        let Some(stencil) = self.poll.take() else {
            return;
        };
        self.polls += 1;
        let mut best: Option<(f64, &Coord)> = None;
        let mut gain = 0.0;
        for (_, pts) in &stencil {
            let b: Vec<Option<f64>> = pts.iter().map(|p| p.as_ref().map(&badness)).collect();
            for (p, b) in pts.iter().zip(&b) {
                if let (Some(p), Some(b)) = (p, b) {
                    if best.is_none_or(|(bb, _)| *b > bb) {
                        best = Some((*b, p));
                    }
                }
            }
            if let [Some(lo), Some(hi)] = b[..] {
                gain += (hi - lo).abs() / 2.0;
            }
        }
        match best {
            Some((b, p)) if b > self.center_badness => {
                self.center = p.clone();
                self.center_badness = b;
            }
            _ => {
                let close = gain <= rules.tolerance * self.center_badness.abs()
                    && self.halvings >= rules.probe_halvings;
                if close || self.step / 2.0 < rules.min_step {
                    self.done = true;
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

    /// Whether two climbs would poll the same stencils from now on.
    pub(crate) fn same_as(&self, other: &Climb) -> bool {
        self.target == other.target
            && self.center == other.center
            && self.step == other.step
            && self.halvings == other.halvings
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
            without.center, start,
            "without a probe the climb stops at its start"
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
}
