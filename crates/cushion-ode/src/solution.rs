//! What a solve returns.

use crate::State;

/// How a solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Reached `t_end`.
    Success,
    /// An event handler (or an early-end request) stopped it.
    StoppedByEvent,
    /// `max_steps` steps were taken.
    MaxSteps,
    /// The step size fell below what `t` can resolve.
    StepTooSmall,
    /// An accepted state (or the initial one) is not finite.
    NonFinite,
    /// The stiffness test fired and the settings say stop.
    Stiff,
    /// The options or the initial state are unusable (non-positive tolerance, `t_end < t0`, ...).
    InvalidInput,
}

impl Status {
    /// True for the two ends that are not failures.
    pub fn is_ok(self) -> bool {
        matches!(self, Status::Success | Status::StoppedByEvent)
    }
}

/// Counts of the work done.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (error too large, a non-finite stage, or a failed solve; under DOP853
    /// also a step taken again to end just past a kinked crossing: `events.rs`).
    pub rejected: u64,
    /// Right-hand-side evaluations, counted as they are made: those of the steps, of the
    /// initial step selection, of restarts, and of finite-difference Jacobians.
    pub rhs_evals: u64,
    /// Jacobians `df/dy` evaluated, analytic or by finite differences (implicit method only).
    pub jacobian_evals: u64,
    /// LU factorizations of the iteration matrix (implicit method only).
    pub lu_decompositions: u64,
    /// Attempts that failed in the linear algebra: a singular iteration matrix (or, for a
    /// Newton-based method, Newton not converging). Each is also a rejected step.
    pub failed_solves: u64,
    /// Changes of method (`Method::Auto`), either way.
    pub method_switches: u64,
    /// Events handled (crossings located), not counting time stops.
    pub events: u64,
    /// Time stops stepped onto.
    pub time_stops: u64,
    /// Whether the stiffness test fired (`Method::Auto`: whether it switched to the implicit
    /// method).
    pub stiff: bool,
    /// When the stiff run of steps that made it fire began.
    pub stiff_since: Option<f64>,
}

/// The work of two solves in a row (a run integrated again from where the first one stopped).
impl std::ops::AddAssign for Stats {
    fn add_assign(&mut self, later: Stats) {
        self.steps += later.steps;
        self.rejected += later.rejected;
        self.rhs_evals += later.rhs_evals;
        self.jacobian_evals += later.jacobian_evals;
        self.lu_decompositions += later.lu_decompositions;
        self.failed_solves += later.failed_solves;
        self.method_switches += later.method_switches;
        self.events += later.events;
        self.time_stops += later.time_stops;
        self.stiff |= later.stiff;
        self.stiff_since = self.stiff_since.or(later.stiff_since);
    }
}

/// One entry of the event log.
#[derive(Clone, Debug, PartialEq)]
pub struct EventRecord<const N: usize> {
    /// Time of the event (on the far side of the crossing).
    pub t: f64,
    /// Index of the event function.
    pub index: usize,
    /// `true` if `g` rose through zero, `false` if it fell.
    pub rising: bool,
    /// The state at `t`, before the handler changed anything.
    pub state: State<N>,
}

/// The result of a solve.
#[derive(Clone, Debug)]
pub struct Solution<const N: usize> {
    pub status: Status,
    /// A sentence for humans when the status is not `Success`.
    pub message: String,
    /// Time reached.
    pub t: f64,
    /// State at `t`.
    pub y: State<N>,
    /// Recorded times and states (see `SolverOptions::output`).
    pub ts: Vec<f64>,
    pub ys: Vec<State<N>>,
    /// Every located event, in time order.
    pub events: Vec<EventRecord<N>>,
    pub stats: Stats,
}
