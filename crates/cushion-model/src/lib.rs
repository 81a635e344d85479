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
//! events and their handlers, Jacobian), `observe` (the observers composed with the model for
//! the integrator, and the trajectory recorder), `peaks` (a run's peaks, found as the steps
//! come), `early_end` (when a run may end early, and its end in closed form after that),
//! `ledger` (the energy ledger), [`simulate`](mod@simulate) (one run: the model and its
//! observers composed), [`summary`](mod@summary), [`trajectory`].

// A negated comparison (`!(x > 0.0)`) is how a value is checked here when NaN must fail the
// check too: clippy would have it written otherwise.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]

pub mod config;
mod early_end;
mod gas_law;
mod ledger;
pub mod model;
mod observe;
mod peaks;
pub mod physics;
pub mod simulate;
pub mod summary;
pub mod trajectory;

pub use config::{ConfigError, KeyInfo, Module, Scene};
pub use simulate::{simulate, simulate_with_ledger, EnergyLedger, RunOptions, RunResult};
pub use summary::{Cell, RunStatus, SolverStats, Summary};
pub use trajectory::{EventLogEntry, Trajectory, TrajectoryPoint};
