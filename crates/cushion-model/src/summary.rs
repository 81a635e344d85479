//! One run's summary row (`docs/model.md`, section "Summary fields").

use serde::Serialize;

/// How a run ended (names and meanings: `docs/model.md`, section "Summary fields").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Ok,
    MaxSteps,
    StepTooSmall,
    NonFinite,
    Stiff,
    Invalid,
}

impl RunStatus {
    /// The name in tables and JSON (`ok`, `max_steps`, ...).
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Ok => "ok",
            RunStatus::MaxSteps => "max_steps",
            RunStatus::StepTooSmall => "step_too_small",
            RunStatus::NonFinite => "non_finite",
            RunStatus::Stiff => "stiff",
            RunStatus::Invalid => "invalid",
        }
    }
}

/// The integrator's counts for one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SolverStats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub events: u64,
    pub stiff: bool,
    /// Jacobians evaluated and LU factorizations made (the implicit method; 0 under dp5).
    pub jacobians: u64,
    pub lu_decompositions: u64,
    /// Changes of method under `solver.method = "auto"`, either way.
    pub method_switches: u64,
}

/// One run's results. Forces in N (signed along +x), times in s, speeds in m/s, momentum in
/// kg m/s, lengths in m, pressures in Pa, impulse in N s.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub status: RunStatus,
    /// Empty when `status` is `ok`; otherwise what went wrong, naming keys and values.
    pub message: String,
    /// When the sensor switched (rigid: first contact); `None` if never.
    pub t_detect: Option<f64>,
    /// When the robot began to brake (`t_detect + dead_time`); `None` if never.
    pub t_brake: Option<f64>,
    /// `F_r` at the time of its largest magnitude (signed; of equal magnitudes, the earliest).
    pub peak_robot_force: f64,
    pub t_peak_robot_force: f64,
    /// Integral of `F_r` over the run.
    pub robot_impulse: f64,
    /// Largest tool-object contact force (0 without an object).
    pub peak_contact_force: f64,
    /// Separate tool-object contact phases.
    pub object_impacts: u32,
    /// Separate contact phases with the forward and the back end-stop (the preload contact
    /// with the forward stop at `t = 0` does not count).
    pub forward_stop_impacts: u32,
    pub back_stop_impacts: u32,
    /// Object speed, momentum and travel `x_p(t_end) - x_p(0)` at `t_end`; `None` without object.
    pub object_final_velocity: Option<f64>,
    pub object_final_momentum: Option<f64>,
    pub object_travel: Option<f64>,
    /// Largest stroke `s` reached.
    pub max_stroke: f64,
    pub back_stop_hit: bool,
    /// Largest gas pressure `p1` (`None` without gas).
    pub max_gas_pressure: Option<f64>,
    /// Energy ledger mismatch over its largest term, the energies held at the start and at the
    /// end counted ([`crate::EnergyLedger::residual`]; `None` with the ledger off).
    pub energy_residual: Option<f64>,
    pub stats: SolverStats,
}

/// One value of a table cell.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    Float(Option<f64>),
    Int(u64),
    Bool(bool),
    Text(String),
}

impl Summary {
    /// Column names of a summary table, in order (stats flattened to `stats_steps`, ...).
    pub const COLUMNS: &'static [&'static str] = &[
        "status",
        "message",
        "t_detect",
        "t_brake",
        "peak_robot_force",
        "t_peak_robot_force",
        "robot_impulse",
        "peak_contact_force",
        "object_impacts",
        "forward_stop_impacts",
        "back_stop_impacts",
        "object_final_velocity",
        "object_final_momentum",
        "object_travel",
        "max_stroke",
        "back_stop_hit",
        "max_gas_pressure",
        "energy_residual",
        "stats_steps",
        "stats_rejected",
        "stats_rhs_evals",
        "stats_events",
        "stats_stiff",
        "stats_jacobians",
        "stats_lu_decompositions",
        "stats_method_switches",
    ];

    /// The cells of this summary, in the order of [`Summary::COLUMNS`].
    pub fn cells(&self) -> Vec<Cell> {
        vec![
            Cell::Text(self.status.name().to_string()),
            Cell::Text(self.message.clone()),
            Cell::Float(self.t_detect),
            Cell::Float(self.t_brake),
            Cell::Float(Some(self.peak_robot_force)),
            Cell::Float(Some(self.t_peak_robot_force)),
            Cell::Float(Some(self.robot_impulse)),
            Cell::Float(Some(self.peak_contact_force)),
            Cell::Int(self.object_impacts as u64),
            Cell::Int(self.forward_stop_impacts as u64),
            Cell::Int(self.back_stop_impacts as u64),
            Cell::Float(self.object_final_velocity),
            Cell::Float(self.object_final_momentum),
            Cell::Float(self.object_travel),
            Cell::Float(Some(self.max_stroke)),
            Cell::Bool(self.back_stop_hit),
            Cell::Float(self.max_gas_pressure),
            Cell::Float(self.energy_residual),
            Cell::Int(self.stats.steps),
            Cell::Int(self.stats.rejected),
            Cell::Int(self.stats.rhs_evals),
            Cell::Int(self.stats.events),
            Cell::Bool(self.stats.stiff),
            Cell::Int(self.stats.jacobians),
            Cell::Int(self.stats.lu_decompositions),
            Cell::Int(self.stats.method_switches),
        ]
    }

    /// A summary of a run that never started (bad input): status `invalid`, zeros elsewhere.
    pub fn invalid(message: impl Into<String>) -> Summary {
        Summary {
            status: RunStatus::Invalid,
            message: message.into(),
            t_detect: None,
            t_brake: None,
            peak_robot_force: 0.0,
            t_peak_robot_force: 0.0,
            robot_impulse: 0.0,
            peak_contact_force: 0.0,
            object_impacts: 0,
            forward_stop_impacts: 0,
            back_stop_impacts: 0,
            object_final_velocity: None,
            object_final_momentum: None,
            object_travel: None,
            max_stroke: 0.0,
            back_stop_hit: false,
            max_gas_pressure: None,
            energy_residual: None,
            stats: SolverStats::default(),
        }
    }
}
