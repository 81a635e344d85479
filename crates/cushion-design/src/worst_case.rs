//! The worst-case search over the `for_all` box for many design points at once, in the batched
//! ask/tell shape: one batch holds the next points of every search still running, so the engine
//! runs them in parallel, and the answer does not depend on how it splits or orders them.
//!
//! Protocol: [`WorstCaseSearch::add`] the design points; then repeatedly
//! [`WorstCaseSearch::ask`] for a batch of runs and [`WorstCaseSearch::tell`] their rows (one
//! per run, in the batch's order, each one value per metric), until `ask` returns an empty
//! batch; then read [`WorstCaseSearch::result`]. Design points may be added between batches.

use crate::axes::{Axes, Point};
use crate::climb::Coord;
use crate::error::{config, DesignError};
use crate::grid::Grid;
use crate::metrics::{Target, Worst};
use crate::point_search::{PointSearch, Shared};

/// The most points a coarse grid may have (one design point's grid is run in one batch).
const MAX_GRID: usize = 1_000_000;

/// How hard the worst case is searched for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchSettings {
    /// Points per range in the coarse grid (every value of a list axis is on it). Default 5.
    pub grid: usize,
    /// Climbs per target, from the worst local candidates of the grid (then from its worst
    /// other points). Default 3.
    pub starts: usize,
    /// How close to the true worst case the climbs must come, relative. Default 1e-3.
    pub tolerance: f64,
    /// The smallest compass step, in normalised units. Default 2^-12.
    pub min_step: f64,
    /// Stencils polled by one climb at most. Default 60.
    pub max_polls: usize,
}

impl Default for SearchSettings {
    fn default() -> SearchSettings {
        SearchSettings {
            grid: 5,
            starts: 3,
            tolerance: 1e-3,
            min_step: 1.0 / 4096.0,
            max_polls: 60,
        }
    }
}

impl SearchSettings {
    pub(crate) fn check(&self) -> Result<(), DesignError> {
        if self.grid < 2 {
            return Err(config(
                "search.grid",
                self.grid,
                "at least 2 points per range",
            ));
        }
        if self.starts < 1 {
            return Err(config("search.starts", self.starts, "at least 1"));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(config(
                "search.tolerance",
                self.tolerance,
                "a number in (0, 1)",
            ));
        }
        if !(self.min_step > 0.0 && self.min_step < 1.0) {
            return Err(config(
                "search.min_step",
                self.min_step,
                "a number in (0, 1)",
            ));
        }
        if self.max_polls < 1 {
            return Err(config("search.max_polls", self.max_polls, "at least 1"));
        }
        Ok(())
    }
}

/// One run the caller must make: a design point and a `for_all` point, both in real units.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    pub design: Point,
    pub for_all: Point,
}

/// The answer at one design point: one worst case per target, and the runs it took.
#[derive(Clone, Debug, PartialEq)]
pub struct WorstCases {
    pub worst: Vec<Worst>,
    pub runs: usize,
}

/// Many design points' worst-case searches, advancing together.
pub struct WorstCaseSearch {
    shared: Shared,
    metrics: usize,
    designs: Vec<(Point, PointSearch)>,
    /// The batch asked for and not yet told: (design id, coordinates) and the runs handed out.
    asked: Vec<(usize, Coord)>,
    batch: Vec<Run>,
}

impl WorstCaseSearch {
    /// A search over `for_all` for `targets`, whose runs report rows of `metrics` values.
    pub fn new(
        for_all: Axes,
        targets: Vec<Target>,
        metrics: usize,
        settings: SearchSettings,
    ) -> Result<WorstCaseSearch, DesignError> {
        settings.check()?;
        if targets.is_empty() {
            return Err(config("limit", "[]", "at least one metric to search"));
        }
        if let Some(t) = targets.iter().find(|t| t.metric >= metrics) {
            return Err(config(
                "target.metric",
                t.metric,
                format!("below {metrics}"),
            ));
        }
        Grid::check_size(&for_all, settings.grid, "search.grid", MAX_GRID)?;
        let continuous = for_all.axes().iter().map(|a| a.is_continuous()).collect();
        Ok(WorstCaseSearch {
            shared: Shared {
                for_all,
                targets,
                settings,
                continuous,
            },
            metrics,
            designs: Vec::new(),
            asked: Vec::new(),
            batch: Vec::new(),
        })
    }

    /// Start the search at a design point (real units); its id is its place in the order of
    /// the calls.
    pub fn add(&mut self, design: Point) -> usize {
        let targets = self.shared.targets.len();
        self.designs.push((design, PointSearch::new(targets)));
        self.designs.len() - 1
    }

    /// The design point of id `id`.
    pub fn design(&self, id: usize) -> Option<&Point> {
        self.designs.get(id).map(|(p, _)| p)
    }

    /// The next batch of runs: design points in id order, each point's runs in its own
    /// order. Empty when every search has finished. Asking again before telling returns the
    /// same batch.
    pub fn ask(&mut self) -> Vec<Run> {
        if self.asked.is_empty() {
            let s = &self.shared;
            for (id, (design, search)) in self.designs.iter_mut().enumerate() {
                for c in search.wanted(s) {
                    self.batch.push(Run {
                        design: design.clone(),
                        for_all: s.for_all.real(&c),
                    });
                    self.asked.push((id, c));
                }
            }
        }
        self.batch.clone()
    }

    /// The rows of the last batch, in its order. A row of the wrong length, or a count other
    /// than the batch's, is refused and changes nothing.
    pub fn tell(&mut self, rows: Vec<Vec<f64>>) -> Result<(), DesignError> {
        if rows.len() != self.asked.len() {
            return Err(DesignError::Protocol(format!(
                "tell: {} rows for a batch of {} runs",
                rows.len(),
                self.asked.len()
            )));
        }
        if let Some(r) = rows.iter().position(|r| r.len() != self.metrics) {
            return Err(DesignError::Protocol(format!(
                "tell: row {r} has {} values, expected one per metric ({})",
                rows[r].len(),
                self.metrics
            )));
        }
        for ((id, c), row) in self.asked.drain(..).zip(rows) {
            self.designs[id].1.receive(&self.shared, c, row);
        }
        self.batch.clear();
        Ok(())
    }

    /// The worst cases at design point `id`, once its search has finished (after an `ask` that
    /// handed out none of its runs).
    pub fn result(&self, id: usize) -> Option<WorstCases> {
        self.designs
            .get(id)
            .and_then(|(_, s)| s.result(&self.shared))
    }

    /// Runs made for all design points.
    pub fn runs(&self) -> usize {
        self.designs.iter().map(|(_, s)| s.runs()).sum()
    }

    pub fn targets(&self) -> &[Target] {
        &self.shared.targets
    }

    pub fn for_all(&self) -> &Axes {
        &self.shared.for_all
    }
}
