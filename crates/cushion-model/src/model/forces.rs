//! The physics at one instant: every force, pressure and power of the scene at a state, for
//! the right-hand side, the samples, the event handlers and the trajectory.

use super::{Model, Regime, MAX_STATES};
use crate::config::Module;
use crate::physics::{self, Segment};
use crate::trajectory::TrajectoryPoint;

/// Everything at one instant: kinematics (m, m/s, m/s^2), pressures (Pa), forces (N, + along
/// +x unless said otherwise), and the ledger's power terms (W).
#[derive(Clone, Copy, Debug, Default)]
pub struct Eval {
    pub x_r: f64,
    pub v_r: f64,
    pub a_r: f64,
    pub x_t: f64,
    pub v_t: f64,
    pub a_t: f64,
    pub x_p: f64,
    pub v_p: f64,
    pub a_p: f64,
    pub s: f64,
    pub sd: f64,
    /// Gas pressure (NaN without gas) and orifice pressure drop.
    pub p1: f64,
    pub dp: f64,
    /// Module force on the tool (`p_m A_p` or `F_b`).
    pub f_module: f64,
    /// Friction on the tool (static while stuck).
    pub f_f: f64,
    /// Magnitudes of the stop forces (forward stop pushes the tool back, back stop forward).
    pub f_fwd: f64,
    pub f_back: f64,
    /// Tool-object contact force (>= 0).
    pub f_c: f64,
    /// Total module force on the tool `G`; the force on the robot is `-G`.
    pub g: f64,
    pub f_r: f64,
    /// Plane friction on the object.
    pub f_plane: f64,
    pub p_work: f64,
    pub p_orifice: f64,
    pub p_friction: f64,
    pub p_contact: f64,
    pub p_plane: f64,
    /// Compressible model: flow through the orifice (m^3/s), `dp_m/dt` (Pa/s), and the power
    /// stored in the liquid (W).
    pub flow: f64,
    pub dp_m: f64,
    pub p_liquid: f64,
}

impl Model {
    /// Everything at `(t, y)` with robot segment `seg` and regime `r`.
    pub(crate) fn eval(&self, t: f64, y: &[f64], seg: &Segment, r: &Regime) -> Eval {
        self.eval_inline(t, y, seg, r)
    }

    /// The module's force on the tool `G` (N, + forward) at stroke `s` and rate `sd`, the rest of
    /// the state as in `y` (same regime): what the tool's equilibrium on its stop and the
    /// oscillator about it are found from (`early_end/linearisation.rs`).
    pub(crate) fn tool_force(&self, t: f64, y: &[f64], seg: &Segment, s: f64, sd: f64) -> f64 {
        let n = self.layout.n.clamp(1, MAX_STATES);
        let mut z = [0.0; MAX_STATES];
        z[..n].copy_from_slice(&y[..n]);
        let i = self.layout.tool.unwrap_or(0);
        let (x_r, v_r, _) = seg.at(t);
        z[i] = x_r - s;
        z[i + 1] = v_r - sd;
        self.eval(t, &z[..n], seg, &self.regime).g
    }

    /// Depth of the holding stop at stroke `s` (m; > 0 in contact).
    pub(crate) fn holding_depth(&self, s: f64) -> f64 {
        if self.regime.fwd {
            -s
        } else {
            s - self.p.stroke
        }
    }

    /// [`Model::eval`], inlined into the hot callers (the right-hand side and the per-step
    /// samples): there the compiler keeps the fields in registers and drops the ones the
    /// caller never reads (the ledger's power terms when the ledger is off, the forces the
    /// right-hand side does not need), instead of filling and copying the whole struct.
    #[inline(always)]
    pub(crate) fn eval_inline(&self, t: f64, y: &[f64], seg: &Segment, r: &Regime) -> Eval {
        let p = &self.p;
        let (x_r, v_r, a_r) = seg.at(t);
        let mut e = Eval {
            x_r,
            v_r,
            a_r,
            p1: f64::NAN,
            x_p: f64::NAN,
            v_p: f64::NAN,
            a_p: f64::NAN,
            ..Eval::default()
        };
        let rigid = p.module == Module::Rigid;
        let mut f_stop = 0.0;
        if let Some(i) = self.layout.tool {
            e.x_t = y[i];
            e.v_t = y[i + 1];
            e.s = x_r - e.x_t;
            e.sd = v_r - e.v_t;
            if r.fwd {
                let d = -e.s;
                e.f_fwd = contact_force(p.k_e, p.chi_e, d, -e.sd, r.stop_released);
                e.p_contact += (e.f_fwd - p.k_e * pos15(d)) * (-e.sd);
            }
            if r.back {
                let d = e.s - p.stroke;
                e.f_back = contact_force(p.k_e, p.chi_e, d, e.sd, r.stop_released);
                e.p_contact += (e.f_back - p.k_e * pos15(d)) * e.sd;
            }
            f_stop = e.f_back - e.f_fwd;
            match p.module {
                Module::Hydraulic if self.layout.liquid.is_some() => {
                    // compressible liquid: p_m is a state; the orifice passes the flow its
                    // pressure drop allows, turbulent (dp = 0.5 c0 rho (Q/A_o)^2 sgn(Q)) down
                    // to the transition pressure, laminar below it
                    let q = self.layout.liquid.unwrap_or(0);
                    let (p_m, v_x) = (y[q], y[q + 1]);
                    e.p1 = self.gas.pressure(v_x);
                    e.dp = p_m - e.p1;
                    e.flow = physics::orifice_flow(p.a_o, p.c0, p.rho, p.p_transition, e.dp);
                    let v_m = p.v_m0 - p.a_p * e.s;
                    e.dp_m = p.beta / v_m * (p.a_p * e.sd - e.flow);
                    e.f_module = p_m * p.a_p;
                    e.p_orifice = e.dp * e.flow;
                    e.p_liquid = p_m * (p.a_p * e.sd - e.flow);
                }
                Module::Hydraulic => {
                    e.p1 = self.gas.pressure(e.s);
                    e.dp = physics::orifice_pressure_drop(p.c0, p.rho, p.a_p, p.a_o, e.sd);
                    if r.cavitating {
                        // the liquid column tears: the chamber holds p_cav, the orifice
                        // carries p_cav - p1
                        e.dp = p.p_cav.unwrap_or(0.0) - e.p1;
                    }
                    e.f_module = (e.p1 + e.dp) * p.a_p;
                    e.p_orifice = e.dp * p.a_p * e.sd;
                }
                Module::Bistable => {
                    e.f_module = physics::bistable_force(p.k_b, p.w, p.h, e.s + p.e);
                }
                Module::Rigid => {}
            }
        } else {
            // Rigid: the tool is the flange.
            e.x_t = x_r;
            e.v_t = v_r;
        }
        if let Some(j) = self.layout.object {
            e.x_p = y[j];
            e.v_p = y[j + 1];
            if r.obj_contact {
                let d = e.x_t - e.x_p;
                let dd = e.v_t - e.v_p;
                e.f_c = contact_force(p.k_c, p.chi_c, d, dd, r.obj_released);
                e.p_contact += (e.f_c - p.k_c * pos15(d)) * dd;
            }
        }
        if rigid {
            e.a_t = a_r;
            e.g = p.m_t * a_r + e.f_c;
        } else if r.tool_stuck {
            e.a_t = a_r;
            e.g = p.m_t * a_r + e.f_c;
            e.f_f = e.g - e.f_module - f_stop;
            e.p_friction = e.f_f * e.sd;
        } else {
            e.f_f = physics::tool_friction(p.d, p.b, e.sd, r.tool_dir);
            e.g = e.f_module + e.f_f + f_stop;
            e.a_t = (e.g - e.f_c) / p.m_t;
            e.p_friction = e.f_f * e.sd;
        }
        e.f_r = -e.g;
        e.p_work = e.g * v_r;
        if self.layout.object.is_some() {
            if p.mu_n > 0.0 {
                if r.obj_stuck {
                    e.a_p = 0.0;
                    e.f_plane = -e.f_c;
                } else {
                    e.f_plane = -p.mu_n;
                    e.a_p = (e.f_c + e.f_plane) / p.m_p;
                    e.p_plane = p.mu_n * e.v_p;
                }
            } else {
                e.a_p = e.f_c / p.m_p;
            }
        }
        e
    }

    /// The trajectory point at `t` (robot segment looked up by time, current regime).
    pub(crate) fn point_at(&self, t: f64, y: &[f64]) -> TrajectoryPoint {
        let seg = *self.robot.segment_at(t);
        let e = self.eval(t, y, &seg, &self.regime);
        to_point(t, &e)
    }
}

/// Hunt–Crossley force of a contact (N, >= 0 while pushing), penetration `d` (m), its rate
/// `dd` (m/s): `d^1.5 (k + chi dd)` while it pushes, 0 once released. The clamp at zero of
/// `physics::hunt_crossley` is the release event here (`EV_*_RELEASE`): inside a step the law
/// stays smooth, and the step that reaches `k + chi dd = 0` is cut there.
#[inline(always)]
fn contact_force(k: f64, chi: f64, d: f64, dd: f64, released: bool) -> f64 {
    if released {
        0.0
    } else {
        pos15(d) * (k + chi * dd)
    }
}

#[inline]
fn pos15(d: f64) -> f64 {
    if d > 0.0 {
        d * d.sqrt()
    } else {
        0.0
    }
}

pub(crate) fn to_point(t: f64, e: &Eval) -> TrajectoryPoint {
    TrajectoryPoint {
        t,
        x_r: e.x_r,
        v_r: e.v_r,
        x_t: e.x_t,
        v_t: e.v_t,
        x_p: e.x_p,
        v_p: e.v_p,
        s: e.s,
        p1: e.p1,
        f_c: e.f_c,
        f_r: e.f_r,
    }
}
