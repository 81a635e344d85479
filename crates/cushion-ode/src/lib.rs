//! `cushion-ode`: an adaptive Dormand–Prince 5(4) integrator with dense output, event
//! detection and location, time stops and Hairer's stiffness test; an adaptive, L-stable
//! Rosenbrock method (Hairer and Wanner's RODAS) for stiff problems; and fixed-step classical
//! RK4 and explicit Euler; Hairer's DOP853 of order 8 for tight tolerances ([`dop853`]);
//! automatic switching between DOPRI5 and the Rosenbrock method
//! ([`auto`]); all behind the same interface and the same loop.
//!
//! It knows ODEs and nothing else. The shape follows SciPy's `integrate/_ivp` and
//! DifferentialEquations.jl: a system ([`OdeSystem`]) is the problem, [`SolverOptions`] picks the
//! method and its settings, [`solve`] orchestrates, and a [`Solution`] carries the final state,
//! the recorded trajectory, the event log and the statistics. Stepping ([`stepper`]), dense
//! output ([`dense`]), step-size control ([`controller`]), events ([`events`]) and the stiffness
//! test ([`stiffness`]) each live in their own file, and so do the loop's step plan
//! (`step_plan.rs`: where the next step ends) and step guard (`step_guard.rs`: whether an
//! accepted step is kept or taken again); the Butcher tableaus are data ([`tableau`]). DOPRI5, the default method, has its own stepper with the coefficients as
//! constants ([`dopri5`]); it gives the same numbers as the generic one reading its tableau.
//! The Rosenbrock method ([`rodas`]) factorizes `I / (h gamma) - J` on the stack like the
//! state (a fixed-size `nalgebra::SMatrix` and an LU with partial pivoting).
//!
//! The state is a fixed-size, stack-allocated `nalgebra::SVector<f64, N>`; nothing is allocated
//! on the heap inside the step loop (the event log and the recorded output grow only when an
//! event fires or a point is recorded).

// A negated comparison (`!(x > 0.0)`) is how a value is checked here when NaN must fail the
// check too: clippy would have it written otherwise.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]

pub mod auto;
pub mod controller;
mod crossing_forecast;
pub mod dense;
pub mod dop853;
pub mod dopri5;
mod event_dip;
mod event_locate;
pub mod events;
mod failure;
pub mod jacobian;
pub mod kinks;
mod lu;
mod norm;
pub mod observer;
pub mod options;
mod record;
mod restart_steps;
pub mod rodas;
pub mod solution;
mod solve;
mod step_guard;
mod step_plan;
pub mod stepper;
pub mod stiffness;
pub mod system;
pub mod tableau;
pub mod test_models;

pub use dense::DenseOutput;
pub use observer::Observer;
pub use options::{Method, Output, SolverOptions, StiffnessAction, Tolerance};
pub use solution::{EventRecord, Solution, Stats, Status};
pub use solve::{solve, solve_observed};
pub use system::{Control, Direction, EventAction, OdeSystem, Step, MAX_EVENTS};

/// The state vector: `N` numbers on the stack.
pub type State<const N: usize> = nalgebra::SVector<f64, N>;

/// An `N` by `N` matrix on the stack (a Jacobian `df/dy`).
pub type Matrix<const N: usize> = nalgebra::SMatrix<f64, N, N>;
