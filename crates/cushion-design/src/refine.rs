//! The design space refined where it matters, above the worst-case searches: a second ask/tell
//! layer. Each design point (a corner of a cell) is judged by its worst cases; cells are split
//! where feasibility changes, where a point is within the tolerance of a limit, and around the
//! best design, down to the resolution.
//!
//! Protocol, as for [`crate::WorstCaseSearch`]: [`Refinement::ask`] for a batch of runs (it holds
//! the next runs of every design point still being searched), [`Refinement::tell`] their rows,
//! until `ask` returns an empty batch. Then [`Refinement::points`], [`Refinement::best`] and
//! [`Refinement::classify`] give the answer.

use std::collections::HashMap;

use crate::axes::{Axes, Point};
use crate::cells::{Cell, Lattice, Node};
use crate::error::{config, DesignError};
use crate::grid::Grid;
use crate::limits::{Limits, Sense};
use crate::metrics::Worst;
use crate::worst_case::{Run, SearchSettings, WorstCaseSearch};

/// How finely the design space is mapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefineSettings {
    /// The finest cell, as a fraction of each design range: rounded down to a power of two
    /// (1/50 maps at 1/64). Default 1/64.
    pub resolution: f64,
    /// Cells per range in the starting grid (rounded up to a power of two, at most
    /// 1/resolution). Default 8 with at most two design ranges, else 4 (9^4 starting corners
    /// would cost more than the refinement).
    pub initial_cells: Option<usize>,
    /// The worst-case search at each design point; its `tolerance` is also the margin within
    /// which a design point counts as on the boundary.
    pub search: SearchSettings,
}

impl Default for RefineSettings {
    fn default() -> RefineSettings {
        RefineSettings {
            resolution: 1.0 / 64.0,
            initial_cells: None,
            search: SearchSettings::default(),
        }
    }
}

/// One evaluated design point: its worst cases and its judgement.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignPoint {
    /// Real units; the index of the value along a list axis.
    pub design: Point,
    /// One per target of [`Limits::targets`].
    pub worst: Vec<Worst>,
    pub feasible: bool,
    pub margin: f64,
    /// The objective's worst case, if there is an objective.
    pub objective: Option<f64>,
    /// Runs spent on this point.
    pub runs: usize,
}

/// A cell of the refined map in real units: its lowest and highest corners.
#[derive(Clone, Debug, PartialEq)]
pub struct CellBounds {
    pub low: Point,
    pub high: Point,
}

/// The refinement of the feasible region of a design question.
pub struct Refinement {
    design: Axes,
    limits: Limits,
    tolerance: f64,
    lattice: Lattice,
    search: WorstCaseSearch,
    /// Lattice point of each design point, by its id in the search.
    nodes: Vec<Node>,
    ids: HashMap<Node, usize>,
    /// Design point ids by bucket (see [`Lattice::bucket_of`]).
    buckets: HashMap<Node, Vec<usize>>,
    /// The judged design points: ids `0..judged.len()`.
    judged: Vec<DesignPoint>,
    cells: Vec<Cell>,
    done: bool,
}

impl Refinement {
    /// The design axes (1 to 4), the `for_all` box (no key in both), the limits, the settings.
    pub fn new(
        design: Axes,
        for_all: Axes,
        limits: Limits,
        settings: RefineSettings,
    ) -> Result<Refinement, DesignError> {
        if design.len() > 4 {
            return Err(config(
                "design",
                format!("{} axes", design.len()),
                "1 to 4 axes",
            ));
        }
        if let Some(a) = design
            .axes()
            .iter()
            .find(|a| for_all.axes().iter().any(|b| b.key == a.key))
        {
            return Err(config(
                &a.key,
                "in design and in for_all",
                "a key in one of them",
            ));
        }
        let n = steps(settings.resolution)?;
        let continuous: Vec<bool> = design.axes().iter().map(|a| a.is_continuous()).collect();
        let ranges = continuous.iter().filter(|&&c| c).count();
        let m = settings
            .initial_cells
            .unwrap_or(if ranges <= 2 { 8 } else { 4 });
        if m == 0 || m > 1 << 16 {
            return Err(config("search.initial_cells", m, "1 to 65536"));
        }
        let m = (m.next_power_of_two() as u32).min(n);
        // The starting corners, each a design point to search: a guard against list axes
        // whose values multiply past what memory holds.
        Grid::check_size(&design, m as usize + 1, "search.initial_cells", 1_000_000)?;
        let search = WorstCaseSearch::new(
            for_all,
            limits.targets().to_vec(),
            limits.metrics().len(),
            settings.search,
        )?;
        let lattice = Lattice {
            n,
            continuous,
            bucket: (n / m).max(1),
        };
        let cells = lattice.initial(&design, m);
        let mut r = Refinement {
            design,
            limits,
            tolerance: settings.search.tolerance,
            lattice,
            search,
            nodes: Vec::new(),
            ids: HashMap::new(),
            buckets: HashMap::new(),
            judged: Vec::new(),
            cells: Vec::new(),
            done: false,
        };
        for c in &cells {
            r.add_corners(c);
        }
        r.cells = cells;
        Ok(r)
    }

    fn add_corners(&mut self, c: &Cell) {
        for node in self.lattice.corners(c) {
            if !self.ids.contains_key(&node) {
                let real = self.design.real(&self.lattice.coordinates(&node));
                let id = self.search.add(real);
                self.ids.insert(node.clone(), id);
                self.buckets
                    .entry(self.lattice.bucket_of(&node))
                    .or_default()
                    .push(id);
                self.nodes.push(node);
            }
        }
    }

    /// The next batch of runs; empty once the map is refined.
    pub fn ask(&mut self) -> Vec<Run> {
        loop {
            let batch = self.search.ask();
            if !batch.is_empty() || self.done {
                return batch;
            }
            self.judge_new();
            if !self.split() {
                self.done = true;
            }
        }
    }

    /// The rows of the last batch, in its order (one value per metric of [`Limits::metrics`]).
    pub fn tell(&mut self, rows: Vec<Vec<f64>>) -> Result<(), DesignError> {
        self.search.tell(rows)
    }

    fn judge_new(&mut self) {
        for id in self.judged.len()..self.nodes.len() {
            let Some(w) = self.search.result(id) else {
                return;
            };
            let j = self.limits.judge(&w.worst);
            self.judged.push(DesignPoint {
                design: self.search.design(id).cloned().unwrap_or_default(),
                worst: w.worst,
                feasible: j.feasible,
                margin: j.margin,
                objective: j.objective,
                runs: w.runs,
            });
        }
    }

    /// One round of splits; false when no cell needs one.
    fn split(&mut self) -> bool {
        let best = self.best_id();
        let mut next = Vec::with_capacity(self.cells.len());
        let mut split = false;
        for cell in std::mem::take(&mut self.cells) {
            if self.needs_split(&cell, best) {
                split = true;
                for child in self.lattice.children(&cell) {
                    self.add_corners(&child);
                    next.push(child);
                }
            } else {
                next.push(cell);
            }
        }
        self.cells = next;
        split
    }

    /// A cell is split (while larger than one lattice step) when the design points in it
    /// (corners, and corners of finer neighbours on its faces) are not all feasible or all
    /// infeasible, when one of them is within the tolerance of a limit, or when it holds the
    /// best design.
    fn needs_split(&self, cell: &Cell, best: Option<usize>) -> bool {
        if cell.size <= 1 {
            return false;
        }
        if best.is_some_and(|b| self.lattice.holds(cell, &self.nodes[b])) {
            return true;
        }
        let mut inside = self
            .lattice
            .buckets_near(cell)
            .into_iter()
            .filter_map(|b| self.buckets.get(&b))
            .flatten()
            .filter(|&&id| self.lattice.holds(cell, &self.nodes[id]))
            .filter_map(|&id| self.judged.get(id).map(|p| (p, id)));
        let Some((first, _)) = inside.next() else {
            return false;
        };
        let near = |p: &DesignPoint| p.margin.abs() <= self.tolerance;
        near(first) || inside.any(|(p, _)| p.feasible != first.feasible || near(p))
    }

    /// The chosen design: with an objective, the feasible point with the best objective (ties:
    /// larger margin); without, the feasible point with the largest margin; with no feasible
    /// point, the point with the largest margin (infeasible: the closest miss). Ties go to the
    /// earlier point.
    fn best_id(&self) -> Option<usize> {
        let any_feasible = self.judged.iter().any(|p| p.feasible);
        let objective = self
            .limits
            .objective()
            .filter(|_| any_feasible)
            .map(|(s, _)| s);
        let better = |a: &DesignPoint, b: &DesignPoint| -> bool {
            if let (Some(s), Some(x), Some(y)) = (objective, a.objective, b.objective) {
                let (x, y) = if s == Sense::Minimize {
                    (-x, -y)
                } else {
                    (x, y)
                };
                if x != y {
                    return x > y;
                }
            }
            a.margin > b.margin
        };
        let mut best: Option<usize> = None;
        for (id, p) in self.judged.iter().enumerate() {
            if (p.feasible || !any_feasible) && best.is_none_or(|b| better(p, &self.judged[b])) {
                best = Some(id);
            }
        }
        best
    }

    /// Whether the map is refined (the last `ask` returned an empty batch).
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Every judged design point, in the order they were added.
    pub fn points(&self) -> &[DesignPoint] {
        &self.judged
    }

    /// The chosen design (see the rule in the crate docs); `None` before any point is judged.
    pub fn best(&self) -> Option<&DesignPoint> {
        self.best_id().map(|b| &self.judged[b])
    }

    /// Runs made in all.
    pub fn runs(&self) -> usize {
        self.search.runs()
    }

    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    pub fn design_axes(&self) -> &Axes {
        &self.design
    }

    pub fn for_all(&self) -> &Axes {
        self.search.for_all()
    }

    /// The cells of the refined map, in real units.
    pub fn cells(&self) -> Vec<CellBounds> {
        self.cells
            .iter()
            .map(|c| {
                let corners = self.lattice.corners(c);
                let real = |n: &Node| self.design.real(&self.lattice.coordinates(n));
                CellBounds {
                    low: real(&corners[0]),
                    high: real(&corners[corners.len() - 1]),
                }
            })
            .collect()
    }

    /// The margin the refined map gives a design point (real units; the index along a list
    /// axis): the multilinear interpolation of the margins at the corners of the cell it falls
    /// in, a failed corner counting as -1 (100 % beyond its limits).
    pub fn map_margin(&self, point: &[f64]) -> Result<f64, DesignError> {
        if !self.done {
            return Err(DesignError::Protocol(
                "the design map is asked for before it is refined".into(),
            ));
        }
        let c = self.design.coordinates(point)?;
        let x: Vec<f64> = c
            .iter()
            .zip(&self.lattice.continuous)
            .map(|(&c, &r)| if r { c * self.lattice.n as f64 } else { c })
            .collect();
        let Some(cell) = self
            .cells
            .iter()
            .find(|cell| self.lattice.holds_position(cell, &x))
        else {
            return Err(DesignError::Protocol(format!(
                "no cell of the map holds {point:?}"
            )));
        };
        let margins: Vec<f64> = self
            .lattice
            .corners(cell)
            .iter()
            .map(|n| {
                let m = self.judged[self.ids[n]].margin;
                if m.is_finite() {
                    m
                } else {
                    -1.0
                }
            })
            .collect();
        Ok(self.lattice.interpolate(cell, &x, &margins))
    }

    /// Whether a design point is feasible by the refined map: its [`Refinement::map_margin`] is
    /// at least 0. At a judged point that is the point's own judgement; in a cell whose corners
    /// are all feasible (or all infeasible) it is theirs; in a cell the boundary crosses, the
    /// side of the interpolated boundary.
    pub fn classify(&self, point: &[f64]) -> Result<bool, DesignError> {
        Ok(self.map_margin(point)? >= 0.0)
    }
}

/// Lattice steps per design range for a resolution: the power of two at least `1/resolution`.
fn steps(resolution: f64) -> Result<u32, DesignError> {
    if !(resolution > 0.0 && resolution <= 1.0) || resolution < 1.0 / (1u32 << 20) as f64 {
        return Err(config(
            "search.resolution",
            resolution,
            "a fraction in [2^-20, 1]",
        ));
    }
    let n = (1.0 / resolution).ceil() as u32;
    Ok(n.next_power_of_two())
}
