//! `cushion-design`: design questions asked of many runs. *Which designs keep every limited
//! metric within its limits for every condition of the `for_all` box, and which is best?* The
//! answer rests on worst cases that are searched for, not sampled, each with its witness.
//!
//! This crate holds the search and nothing else: it knows no model and runs nothing. It asks
//! for batches of runs (a design point and a `for_all` point each, in real units) and is told
//! each run's metric values, so one parallel engine can run every batch, and a test can run it
//! with a closure.
//!
//! # The worst case at one design point
//!
//! For every target (a limited metric and which end of it is bad: the largest value, the
//! smallest, or the largest size `|value|`), all targets at once:
//!
//! 1. **Coarse grid.** Every point of a grid over the `for_all` box: `grid` points per range
//!    (default 5, ends included; evenly spaced in the logarithm on a log scale) times every
//!    value of every list axis.
//! 2. **Starts.** For each target, the grid points no neighbour of which along a range is worse
//!    (the grid's local worst cases), worst first; the `starts` worst of them (default 3). Where
//!    the grid has fewer local worst cases, its worst other points take the starts left.
//! 3. **Climbs.** From each start, a compass search in the normalised box (each range mapped
//!    onto `[0, 1]`): poll the neighbours at `step` along every range (the first step is half the
//!    grid spacing, so the first poll lands between grid points; a start that is not a local
//!    worst case polls its first stencil at half the step too), move to the worst neighbour if
//!    it is worse than the centre, else halve the step. A climb would stop when the gain left
//!    near its centre, estimated from the stencil (`|b(c+h) - b(c-h)| / 2` summed over the
//!    ranges, which bounds the gain of a smooth peak and equals that of a kink `|x - a|`), is
//!    within `tolerance` (relative, default 1e-3) of the centre's value, or the step falls under
//!    `min_step`; it then polls once the faces of the box through its centre along every range,
//!    and goes on from the worst with its first step if that is as bad as the centre to within
//!    `tolerance` (a plateau that ends at a face, with a ridge rising towards it). It stops at
//!    the next such point, or after `max_polls` stencils. List axes stay at the start's value:
//!    their values are unordered and the grid has them all.
//! 4. **The answer.** Every run updates every target: a target's worst case is the worst run
//!    made at that design point, for any target's climb, and its witness the `for_all` point of
//!    that run. The value is the run's own number, so running the witness again gives it to the
//!    bit. A failed run (a metric not finite: the caller passes `NaN` for a run whose status is
//!    not `ok`) violates every limit: it becomes every target's worst case and the search stops.
//!
//! No point is run twice at a design point (the runs are keyed by their exact coordinates), and
//! each design point counts its runs. The search is deterministic: the batches, their order and
//! the decisions depend only on the values told, never on how the caller splits or orders the
//! runs of a batch, nor on the other design points in it.
//!
//! **When it can miss the worst case.** The worst value found is always a real run, so it never
//! lies above the true worst case; it can lie below it when:
//! - a peak is narrower than the coarse grid's spacing and no start's climb walks into it: no
//!   grid point near it is a local worst case of the grid or among the worst points that take
//!   the starts left (a rising slope behind it hides it), or better local candidates take all
//!   `starts`. A 5-point grid spaces ranges by a quarter;
//! - a climb stops early: a narrow ridge oblique to the axes that does not end on a face of the
//!   box, which the compass stencil sees only at small steps, or a peak that sits
//!   symmetrically between a centre's two neighbours;
//! - a peak lies within half a step of the edge of the box from a centre on the edge (a centre
//!   on the edge counts no gain across it, which is what finds worst cases on the edge);
//! - a list axis value that no start takes (its values only meet the grid and the starts).
//!
//! # The design space
//!
//! The design axes (1 to 4) form a lattice: each range cut into a power of two steps at least
//! `1/resolution` (default 64), lists value by value. It starts from a grid of cells
//! (`initial_cells` per range: 8, or 4 beyond two ranges) and works in rounds. Every corner is a
//! design point, searched for its worst cases as above (corners shared by cells are searched
//! once); then judged against the limits: feasible, and its margin, the smallest relative
//! distance of its worst cases to their limits (negative when violated, `-inf` for a failed run;
//! see [`limits`]). Then every cell larger than one step is halved along every range (into 4, 8
//! or 16) when the design points in its closed box (its corners and the corners of finer
//! neighbours on its faces) are not all feasible or all infeasible, when one of them is within
//! `tolerance` of a limit (`|margin| <= tolerance`), or when it holds the best design. The new
//! corners are searched in the next batches, all design points together. It stops when no cell
//! splits. A cell whose corners are all inside (or all outside) by more than the tolerance is
//! never split, so a feasible island or hole that no corner of a coarse cell sees is missed, as
//! a peak between grid points is.
//!
//! **The best design**: with an objective, the feasible design point whose objective (the
//! worst case of one limited metric: its largest value to minimize, its smallest to maximize)
//! is best, ties to the larger margin; without one, the feasible point with the largest margin.
//! With no feasible point, the point with the largest margin (the closest miss; its `feasible`
//! says so). Further ties go to the earlier point.
//!
//! **Classification**: a design point is feasible by the refined map when the multilinear
//! interpolation of the margins at the corners of the cell it falls in is at least 0 (cells are
//! half-open, the top of each range belonging to the last cell; a failed corner counts as
//! margin -1). At a corner this is its own judgement, in a cell with all corners on one side
//! it is theirs, and across the boundary it follows the interpolated boundary.
//!
//! # Verification
//!
//! [`verify_grid`] lists the `for_all` points of a fine grid (`n` per range, every list value)
//! and [`check`] judges the runs of the chosen design there: whether every run meets every
//! limit, and the worst case found on that grid.
//!
//! # Answered by the model
//!
//! Above the core, and the only modules that know the model and the sweep engine:
//! `design_file` (the TOML design file, checked: [`DesignFile`]), `engine_runs` (every batch of
//! the refinement, then the verification grid, run through the sweep crate's parallel engine:
//! [`compute_design`] gives a [`DesignResult`] in memory), `tables` (the design points as an
//! Arrow record batch, `answer.json`), `design_map` (`design-map.svg`) and `output` (the output
//! folder: [`run_design`] computes and writes it).
//!
//! # Modules, each using only those before it
//! `error`; `axes` (the boxes), `grid`, `metrics` (targets and worst cases), `limits` (limits,
//! objective, judgement); `climb` (one compass search), `point_search` (one design point),
//! `worst_case` (many, batched); `cells` (the design lattice), `refine` (the design map);
//! `verify`; then `design_file`, `engine_runs`, `tables`, `design_map`, `output`.

pub mod axes;
mod cells;
mod climb;
pub mod error;
mod grid;
pub mod limits;
pub mod metrics;
mod point_search;
pub mod refine;
pub mod verify;
pub mod worst_case;

pub mod design_file;
pub mod design_map;
pub mod engine_runs;
pub mod output;
pub mod tables;

pub use axes::{Axes, Axis, AxisKind, Point, Scale};
pub use design_file::{DesignFile, SearchOptions};
pub use engine_runs::{compute_design, compute_design_with, DesignResult};
pub use error::DesignError;
pub use limits::{Judgement, Limit, Limits, Objective, Sense};
pub use metrics::{Direction, Target, Worst};
pub use output::{run_design, run_design_with, DesignOptions, DesignOutcome};
pub use refine::{CellBounds, DesignPoint, RefineSettings, Refinement};
pub use tables::{answer_json, design_table};
pub use verify::{check, verify_grid, Verification};
pub use worst_case::{Run, SearchSettings, WorstCaseSearch, WorstCases};
