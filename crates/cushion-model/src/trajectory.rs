//! Trajectories and the event log of one run (`docs/model.md`, sections "Summary fields" and
//! "Events and regimes").

use serde::Serialize;

/// The scene at one instant. Positions in m (frames of `docs/model.md`, "Scene and frames"),
/// speeds in m/s, `p1` in
/// Pa, forces in N. Quantities a scene does not have (no object, no gas) are NaN (null in JSON).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TrajectoryPoint {
    pub t: f64,
    pub x_r: f64,
    pub v_r: f64,
    pub x_t: f64,
    pub v_t: f64,
    pub x_p: f64,
    pub v_p: f64,
    /// Stroke `x_r - x_t`.
    pub s: f64,
    /// Gas pressure.
    pub p1: f64,
    /// Tool-object contact force (>= 0, pushes the object along +x).
    pub f_c: f64,
    /// Force of the module on the robot flange.
    pub f_r: f64,
}

impl TrajectoryPoint {
    /// Column names, in the order of [`TrajectoryPoint::values`].
    pub const COLUMNS: [&'static str; 11] = [
        "t", "x_r", "v_r", "x_t", "v_t", "x_p", "v_p", "s", "p1", "F_c", "F_r",
    ];

    pub fn values(&self) -> [f64; 11] {
        [
            self.t, self.x_r, self.v_r, self.x_t, self.v_t, self.x_p, self.v_p, self.s, self.p1,
            self.f_c, self.f_r,
        ]
    }
}

/// Recorded points, ascending in time.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Trajectory {
    pub points: Vec<TrajectoryPoint>,
}

/// One event of a run: its time, its name and the scene at that instant.
/// Names: `sensor`, `brake`, `robot_stopped`, `robot_cruising` (end of acceleration),
/// `object_contact_begin`, `object_contact_end`, `forward_stop_begin`, `forward_stop_end`,
/// `back_stop_begin`, `back_stop_end`, `tool_stick`, `tool_slip`, `object_stick`,
/// `object_slip`, `cavitation_begin`, `cavitation_end` (with `hydraulic.cavitation`),
/// `early_end`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EventLogEntry {
    pub t: f64,
    pub name: String,
    pub point: TrajectoryPoint,
}
