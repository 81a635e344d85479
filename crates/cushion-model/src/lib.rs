//! `cushion-model`: the physics of `shared/SPEC.md`.
//!
//! A [`Scene`] (the TOML keys of SPEC section 7) is checked, then assembled into an ODE system
//! holding only the parts it names, solved with `cushion-ode`, and reduced to a [`Summary`]
//! (SPEC section 5) and, when asked, a [`Trajectory`] and the event log.
//!
//! Frames (SPEC section 1): +x is the direction of approach; `x_r` flange, `x_t` tool face,
//! `x_p` object face; stroke `s = x_r - x_t` (0 at the forward stop, `L` at the back stop).
//! SI units throughout.
//!
//! Modules: [`config`] (scene keys, defaults, validation), [`physics`] (force laws, robot
//! profile, preload equilibrium), [`model`] (the ODE system, events, metrics), [`simulate`]
//! (one run), [`summary`], [`trajectory`].

pub mod config;
pub mod model;
pub mod physics;
pub mod simulate;
pub mod summary;
pub mod trajectory;

pub use config::{ConfigError, Module, Scene};
pub use simulate::{simulate, RunOptions, RunResult};
pub use summary::{Cell, RunStatus, SolverStats, Summary};
pub use trajectory::{EventLogEntry, Trajectory, TrajectoryPoint};
