//! `cushion-model`: the physics of `docs/model.md`.
//!
//! A [`Scene`] (the TOML keys of `docs/scene-keys.md`) is checked, then assembled into an ODE
//! system holding only the parts it names, solved with `cushion-ode`, and reduced to a
//! [`Summary`] (`docs/model.md`, "Summary fields") and, when asked, a [`Trajectory`] and the
//! event log.
//!
//! Frames (`docs/model.md`, "Scene and frames"): +x is the direction of approach; `x_r` flange,
//! `x_t` tool face, `x_p` object face; stroke `s = x_r - x_t` (0 at the forward stop, `L` at the
//! back stop). SI units throughout.
//!
//! # Modelling choices (where the paper is silent, or where physics asked for more)
//!
//! - **Contacts** (Hunt–Crossley) are clamped at `F >= 0`: the unclamped law pulls the bodies
//!   together during fast restitution (`dd < -k/chi`, 0.44 m/s for the paper's values). The
//!   energy ledger books elastic energy `k d^2.5/2.5` and dissipation `(F - k d^1.5) dd >= 0`.
//!   The clamp is a regime, not a `max`: an event releases a contact when `k + chi dd` falls
//!   through zero while the bodies overlap (force 0 from then on) and makes it push again if
//!   `k + chi dd` rises above `1e-12 k`, so no step integrates across the kink (inside a step,
//!   DOPRI5's error estimate does not see a kink for what it is, and the error stops following
//!   the tolerance:
//!   `tests/friction_and_contacts.rs::a_contact_released_before_the_bodies_part_converges_with_the_tolerance`).
//!   Contact begin/end are events; a contact begins at a penetration of 1e-14 m and ends at 0
//!   (a hysteresis far below any force that matters, `k 1e-21 N`), so that a touch right after
//!   an end is never lost to the integrator's rule that a function starting a step at exactly
//!   zero does not fire.
//! - **Preload**: the initial stroke `s0 < 0` solves `k_e (-s0)^1.5 = p1(s0) A_p` (bistable:
//!   `F_b(s0 + e)`) by bracketed regula falsi; the contact with the forward stop at `t = 0` is
//!   not counted in `forward_stop_impacts`. The sensor threshold is measured from `s = 0`.
//! - **Robot**: cruising start, or rest start with a time stop at the end of the acceleration;
//!   the sensor (rigid: first contact) schedules the brake as a time stop at
//!   `t_detect + dead_time` (`dead_time = 0`: braking starts at the event), the brake schedules
//!   the stop. `t_brake` is `None` when that time falls after the run.
//! - **Dry friction on the tool** (`d > 0`): the tool starts stuck when friction can hold it; while
//!   stuck it moves with the flange and friction is whatever holds it there; it slips when that
//!   exceeds `d` (direction: the sign of the needed force), and sticks again when `sd` returns
//!   to zero and `d` can hold it; when `d` cannot, it slips back the other way. No smoothing.
//!   The stick event fires when `sd` passes 1e-12 m/s beyond zero (the object's: `v_p`
//!   below -1e-12 m/s), so that a slip, which begins at a speed of exactly zero, starts its
//!   event function on the side it slips to and a quick return is seen.
//! - **Plane friction** (`mu > 0`): the object starts stuck, slips once `F_c > mu m_p g`, sticks
//!   again when its speed returns to zero with `F_c <= mu m_p g`. It only slides forward (the
//!   tool can only push).
//! - **Robot impulse** `int F_r dt` follows exactly from momentum
//!   (`-(m_t dv_t + m_p dv_p)`; with plane friction a quadrature of `F_c` replaces `m_p dv_p`).
//! - **Peaks** (`|F_r|`, `F_c`, stroke) are sampled at each step's end, and at three interior
//!   points of its dense output where a new peak is possible (an end value above half the
//!   peak so far, the stroke turning, the steps right after an event); every local top of the
//!   samples near the largest value so far is located at once by Brent's search on the dense
//!   output around it (`peaks/`). `max_gas_pressure = p1(max_stroke)` (monotone in `s`).
//! - **Early end** (`solver.early_end`): see [`simulate()`]; the summary equals the full run's to
//!   the tolerance (tested). Besides the standing robot, the same end is taken while the robot
//!   cruises on with no brake before `t_end` (a preload too strong for the sensor to switch, or
//!   a dead time past the run), once the object is gone and the tool is stuck or at rest on its
//!   stop (`early_end/riding.rs`): nothing can change any more there either.
//! - **Ringing tail** (`solver.ringing_tail`, with early end): once only the tool's small ringing
//!   on its stop is left (the robot braking, standing, or cruising with a known motion to
//!   `t_end`), the run ends and that ringing is written in closed form (averaging method,
//!   `early_end/ringing.rs`), where it can change no summary value and its predicted error in
//!   the robot impulse is below `rtol (m_t + m_p) v_max` (`early_end/ringing_search.rs`; tested
//!   against running to
//!   `t_end`).
//! - **Cavitation** (extension, off by default): `p_m >= hydraulic.cavitation_pressure`, with
//!   events at its onset and end; the orifice then carries `p_cav - p1`.
//! - **Compressible liquid** (`docs/model.md`, "Compressible liquid",
//!   `hydraulic.bulk_modulus > 0`): the main chamber pressure `p_m` and the liquid volume moved
//!   through the orifice `V_x` become states,
//!   `dp_m/dt = beta / (V_m0 - A_p s) (A_p sd - Q)`, `dV_x/dt = Q`, the orifice passes
//!   `Q = A_o sgn(p_m - p1) sqrt(2 |p_m - p1| / (c0 rho))` (the lumped law solved for the flow),
//!   the gas sees `V_g = V_g0 - V_x`; the tool feels `p_m A_p`. It starts at rest (`p_m = p1`).
//!   Over the paper's impact it agrees with the lumped model to 1e-4 (peak forces, stroke, gas
//!   pressure; tested) and costs about 1000 times the steps: DOPRI5 finds it stiff (status `stiff`
//!   with `solver.stiffness = "stop"`), which is where an explicit method stops being usable.
//!   The energy ledger adds the liquid's compression energy as a quadrature. Cavitation applies
//!   to the lumped model only.
//! - **Validation**: every number must be finite; a part's keys constrain only the scenes that
//!   have the part (the hydraulic section a hydraulic scene, the chamber volume only a
//!   compressible liquid, ...), and a sweep checks every run's own scene before its first run,
//!   so a sweep switching the module never meets an invalid run at run time.
//!   `object.gap` must be `> 0` (a touching start has no contact event),
//!   `hydraulic.gas_pressure > 0`, `hydraulic.gas_exponent` in `(1, 2]`, `bistable.offset` in
//!   `[0, h)`.
//! - **Stiffness**: the tool resting on its Hertzian stop makes long explicit steps stiff;
//!   Hairer's test then sets `stats.stiff` (`solver.stiffness = "warn"`, the default) and the
//!   run stays `ok` with an empty message, or ends with status `stiff` (`"stop"`).
//!
//! ## Where the paper's text and this model differ
//!
//! The paper's first result holds as `docs/model.md` words it (section "The paper's four results"),
//! but the paper also says the gas pressure is largest "in correspondence to the instant in which
//! the robot starts decelerating". Here (paper Table 1 values, sign-correct orifice) the gas
//! pressure peaks earlier, at about 38 ms, when tool and object have been brought back to the
//! robot's speed (`sd = 0`, the largest stroke); it then falls slowly while gas and orifice push
//! tool and object slightly ahead of the robot, and falls fast once the robot brakes (74.6 ms) and
//! the tool outruns it. With the paper's unsigned orifice law (`dp >= 0` both ways) the maximum of
//! `s` is also where `sd = 0`, so the difference is not the sign fix; the paper's parameters may
//! differ from the table as read (its labels are garbled).
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
