//! `cushion-model`: the physics of `docs/model.md`.
//!
//! A [`Scene`] (the TOML keys of `docs/scene-keys.md`) is checked, then assembled into an ODE
//! system holding only the parts it names, solved with `cushion-ode`, and reduced to a
//! [`Summary`] (`docs/model.md`, "Summary fields") and, when asked, a [`Trajectory`] and the
//! event log.
//!
//! The equations, the modelling choices (clamped contacts, stick–slip friction, the preload
//! equilibrium, peaks, the early end and the ringing tail, the compressible liquid), the
//! validation rules and where the model departs from the paper are documented once, in
//! `docs/model.md`; the integrator in `docs/integrator.md`.
//!
//! Modules: [`config`] (scene keys, defaults, validation), [`physics`] (force laws, robot
//! profile, preload equilibrium), [`model`] (the physics as an ODE system: right-hand side,
//! events and their handlers, Jacobian), `observe` (what watches a run: the peaks, the early
//! end, the trajectory recorder), `tail` (a run's end in closed form after its early end),
//! `ledger` (the energy ledger), [`simulate`](mod@simulate) (one run: the model and its
//! observers composed), [`summary`](mod@summary), [`trajectory`].

// A negated comparison (`!(x > 0.0)`) is how a value is checked here when NaN must fail the
// check too: clippy would have it written otherwise.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]

pub mod config;
mod gas_law;
mod ledger;
pub mod model;
mod observe;
mod peaks;
pub mod physics;
mod resting;
mod ringing;
mod ringing_tail;
pub mod simulate;
pub mod summary;
mod tail;
pub mod trajectory;

pub use config::{ConfigError, KeyInfo, Module, Scene};
pub use simulate::{simulate, simulate_with_ledger, EnergyLedger, RunOptions, RunResult};
pub use summary::{Cell, RunStatus, SolverStats, Summary};
pub use trajectory::{EventLogEntry, Trajectory, TrajectoryPoint};
