//! The worst-case search at one design point, for all its targets at once: the coarse grid,
//! then the climbs from the grid's worst local candidates, each point run once.
//!
//! It is a state machine driven from outside: [`PointSearch::wanted`] says which `for_all`
//! points it needs next (an empty list once it has finished), [`PointSearch::receive`] takes a
//! run's row. Every run's row updates every target's worst case, so a climb for one metric can
//! find another metric's worst case too.

use std::collections::HashMap;

use crate::axes::Axes;
use crate::climb::{Climb, Coord, Rules, PROBE_HALVINGS};
use crate::grid::Grid;
use crate::metrics::{failed, Target, Worst};
use crate::worst_case::{SearchSettings, WorstCases};

/// What every point search shares: the box, the targets and the settings.
pub(crate) struct Shared {
    pub(crate) for_all: Axes,
    pub(crate) targets: Vec<Target>,
    pub(crate) settings: SearchSettings,
    pub(crate) continuous: Vec<bool>,
}

enum Stage {
    Grid,
    Climbing(Vec<Climb>),
    Done,
}

pub(crate) struct PointSearch {
    /// Coordinates of each run made, and its row, in the order the runs were asked for.
    runs: Vec<(Coord, Vec<f64>)>,
    /// The run at each point (by the bits of its coordinates: the same point is never run twice).
    seen: HashMap<Vec<u64>, usize>,
    /// Per target, the run that is its worst case so far.
    worst: Vec<Option<usize>>,
    /// The first failed run: it is every target's worst case, and the search stops.
    failed: Option<usize>,
    stage: Stage,
}

fn key(c: &[f64]) -> Vec<u64> {
    c.iter().map(|x| x.to_bits()).collect()
}

impl PointSearch {
    pub(crate) fn new(targets: usize) -> PointSearch {
        PointSearch {
            runs: Vec::new(),
            seen: HashMap::new(),
            worst: vec![None; targets],
            failed: None,
            stage: Stage::Grid,
        }
    }

    /// The points to run next, none of them run before; empty once the search has finished.
    pub(crate) fn wanted(&mut self, s: &Shared) -> Vec<Coord> {
        loop {
            if self.failed.is_some() {
                self.stage = Stage::Done;
            }
            match std::mem::replace(&mut self.stage, Stage::Done) {
                Stage::Done => return Vec::new(),
                Stage::Grid => {
                    let grid = Grid::new(&s.for_all, s.settings.grid);
                    let missing = self.missing(grid.points());
                    if !missing.is_empty() {
                        self.stage = Stage::Grid;
                        return missing;
                    }
                    self.stage = Stage::Climbing(self.starts(s, &grid));
                }
                Stage::Climbing(mut climbs) => {
                    let polls = climbs
                        .iter_mut()
                        .flat_map(|c| c.poll(&s.continuous))
                        .collect();
                    let missing = self.missing(polls);
                    if missing.is_empty() {
                        self.decide(s, &mut climbs);
                    }
                    if !climbs.is_empty() {
                        self.stage = Stage::Climbing(climbs);
                    }
                    if !missing.is_empty() {
                        return missing;
                    }
                }
            }
        }
    }

    /// Of `points`, those not run yet, each once, in order.
    fn missing(&self, points: Vec<Coord>) -> Vec<Coord> {
        let mut asked = std::collections::HashSet::new();
        points
            .into_iter()
            .filter(|p| {
                let k = key(p);
                !self.seen.contains_key(&k) && asked.insert(k)
            })
            .collect()
    }

    fn badness(&self, s: &Shared, target: usize, run: usize) -> f64 {
        let t = s.targets[target];
        t.direction.badness(self.runs[run].1[t.metric])
    }

    /// Every climb decides on its polled stencil; finished climbs and climbs that now repeat an
    /// earlier one are dropped.
    fn decide(&self, s: &Shared, climbs: &mut Vec<Climb>) {
        let rules = Rules {
            tolerance: s.settings.tolerance,
            min_step: s.settings.min_step,
            max_polls: s.settings.max_polls,
            probe_halvings: PROBE_HALVINGS,
        };
        for c in climbs.iter_mut() {
            let target = c.target;
            c.decide(|p| self.badness(s, target, self.seen[&key(p)]), &rules);
        }
        let mut kept: Vec<Climb> = Vec::new();
        for c in climbs.drain(..) {
            if !c.done && !kept.iter().any(|k| k.same_as(&c)) {
                kept.push(c);
            }
        }
        *climbs = kept;
    }

    /// The climbs' starts: for each target, its `starts` worst grid points among those no
    /// range neighbour of which is worse (the grid's local worst cases: a climb from elsewhere
    /// would mostly end on the same one), worst first, ties in grid order; where the grid has
    /// fewer local worst cases, its worst other points, whose climbs poll their first stencil
    /// at half the step too (see `climb`).
    fn starts(&self, s: &Shared, grid: &Grid) -> Vec<Climb> {
        let step = 0.5 / (s.settings.grid.max(2) - 1) as f64;
        let run_of: Vec<usize> = grid.points().iter().map(|p| self.seen[&key(p)]).collect();
        let mut climbs = Vec::new();
        for target in 0..s.targets.len() {
            let b: Vec<f64> = run_of.iter().map(|&r| self.badness(s, target, r)).collect();
            let local: Vec<bool> = (0..grid.len())
                .map(|k| grid.neighbours(k).iter().all(|&n| b[n] <= b[k]))
                .collect();
            let mut order: Vec<usize> = (0..grid.len()).collect();
            // A stable sort keeps grid order among ties: local worst cases first, worst first.
            order.sort_by(|&x, &y| local[y].cmp(&local[x]).then(b[y].total_cmp(&b[x])));
            for &k in order.iter().take(s.settings.starts) {
                let start = if local[k] {
                    Climb::new
                } else {
                    Climb::from_slope
                };
                climbs.push(start(target, grid.point(k), b[k], step));
            }
        }
        climbs
    }

    /// Take the row of the run at `point`.
    pub(crate) fn receive(&mut self, s: &Shared, point: Coord, row: Vec<f64>) {
        let run = self.runs.len();
        self.seen.insert(key(&point), run);
        let bad = failed(&row);
        self.runs.push((point, row));
        if bad {
            self.failed.get_or_insert(run);
            return;
        }
        for target in 0..s.targets.len() {
            let worse = match self.worst[target] {
                None => true,
                Some(w) => self.badness(s, target, run) > self.badness(s, target, w),
            };
            if worse {
                self.worst[target] = Some(run);
            }
        }
    }

    /// Runs made so far.
    pub(crate) fn runs(&self) -> usize {
        self.runs.len()
    }

    /// The worst cases, once the search has finished.
    pub(crate) fn result(&self, s: &Shared) -> Option<WorstCases> {
        if !matches!(self.stage, Stage::Done) {
            return None;
        }
        let worst = (0..s.targets.len())
            .map(|target| match (self.failed, self.worst[target]) {
                (Some(run), _) => Worst {
                    value: f64::NAN,
                    witness: s.for_all.real(&self.runs[run].0),
                    failed: true,
                },
                (None, Some(run)) => Worst {
                    value: self.runs[run].1[s.targets[target].metric],
                    witness: s.for_all.real(&self.runs[run].0),
                    failed: false,
                },
                // A finished search has run its grid, so every target has a worst case.
                (None, None) => Worst {
                    value: f64::NAN,
                    witness: Vec::new(),
                    failed: true,
                },
            })
            .collect();
        Some(WorstCases {
            worst,
            runs: self.runs.len(),
        })
    }
}
