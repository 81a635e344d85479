//! The scene's event functions: which ones it has ([`EventSet`]), their values at a state,
//! how far they can stray from their chord inside a step, and what each does when it fires
//! (a contact begins or ends, a part sticks or slips, the sensor switches, the robot brakes).

use super::{to_point, Model};
use crate::config::Module;
use crate::physics::{self, Segment};
use crate::trajectory::EventLogEntry;
use cushion_ode::{Control, EventAction};

/// The flange and tool kinematics every event function starts from, computed once per
/// `events` call: flange `x_r` (m), `v_r` (m/s) on the current robot segment `seg`, tool `x_t`,
/// `v_t` (the flange itself for the rigid module).
pub(super) struct EventKinematics<'a> {
    seg: &'a Segment,
    x_r: f64,
    v_r: f64,
    x_t: f64,
    v_t: f64,
}

impl<'a> EventKinematics<'a> {
    #[inline(always)]
    pub(super) fn at(m: &'a Model, t: f64, y: &[f64]) -> EventKinematics<'a> {
        let seg = m.robot.current();
        let (x_r, v_r, _) = seg.at(t);
        let (x_t, v_t) = match m.layout.tool {
            Some(i) => (y[i], y[i + 1]),
            None => (x_r, v_r),
        };
        EventKinematics {
            seg,
            x_r,
            v_r,
            x_t,
            v_t,
        }
    }
}

// The margins below keep each switch's function strictly on its side right after its event.
// The integrator gives a function that is exactly zero after a handler the side it moves to
// (it looks a moment past the zero, as CVODE does: `cushion_ode::events`), but that serves
// only where the function moves by more than its rounding within the look: a slip that begins
// as the holding force just passes the friction limit accelerates by about 1e-9 d / m_t, and a
// heavily damped contact's `k + chi dd` can cross zero as the penetration rate levels off.
// Without the margins, `tests/model/friction_and_contacts.rs::a_reverse_slip_after_a_failed_stick_test_is_followed`
// chatters through thousands of failed stick tests at one instant, and a scene of
// `tests/wide_scenes.rs` loses its energy ledger.

/// Penetration (m) at which a contact begins; it ends at zero (see `event_value`). Its force
/// there, `k 1e-21`, is below 1e-15 N for the stiffnesses of the paper.
const CONTACT_HYSTERESIS: f64 = 1e-14;

/// Relative margin by which the holding force must exceed the friction limit for a stuck tool
/// or object to slip. A part sticks with a holding force just under the limit; its stuck value
/// is then constant only up to rounding (a few ulp of the forces it is the difference of), and
/// without the margin that noise could set off a slip a moment later and a stick right after
/// (`tests/model/friction_and_contacts.rs::a_stuck_tool_slips_only_when_its_load_changes`).
const STICK_HYSTERESIS: f64 = 1e-9;

/// Speed (m/s) past zero at which a slipping part's stick test runs: its event function is
/// its slip speed plus this on the side it slips to (the tool: `sd + dir 1e-12`; the object,
/// which slides forward only: `v_p + 1e-12`). A slip begins at a speed of zero, and a function
/// that starts a step at exactly zero never fires there; without the margin, a reverse slip
/// that turns back within the step after a failed stick test is invisible, and the tool goes
/// on slipping with its friction pushing instead of braking, until its speed next passes zero
/// (`tests/model/friction_and_contacts.rs::a_reverse_slip_after_a_failed_stick_test_is_followed`).
const SLIP_HYSTERESIS: f64 = 1e-12;

/// Relative margin (of `k`) by which `k + chi dd` must rise above zero for a released contact
/// to push again (see `release_value`).
const RELEASE_HYSTERESIS: f64 = 1e-12;

pub(super) const EV_SENSOR: u8 = 0;
pub(super) const EV_OBJECT: u8 = 1;
pub(super) const EV_FWD: u8 = 2;
pub(super) const EV_BACK: u8 = 3;
pub(super) const EV_TOOL_STICK: u8 = 4;
pub(super) const EV_OBJ_STICK: u8 = 5;
pub(super) const EV_CAVITATION: u8 = 6;
pub(super) const EV_OBJ_RELEASE: u8 = 7;
pub(super) const EV_STOP_RELEASE: u8 = 8;

/// Which event functions a scene has. [`EventSet::visit`] lists their kinds in one fixed order,
/// the order of `Model::events` (their indices for the integrator).
#[derive(Clone, Copy, Debug)]
pub(super) struct EventSet {
    /// Sensor, both end-stops and the stop release (hydraulic and bistable).
    pub(super) tool: bool,
    /// Tool-object contact and its release.
    pub(super) object: bool,
    /// Stick and slip of the tool (`tool.dry_friction > 0`).
    pub(super) tool_stick: bool,
    /// Stick and slip of the object (plane friction).
    pub(super) object_stick: bool,
    pub(super) cavitation: bool,
}

impl EventSet {
    /// Call `f` with each kind the scene has, in index order. Inlined, each call's kind is a
    /// constant, so `f` can resolve its `match` on the kind at compile time: evaluating the
    /// functions this way takes a fixed series of branches that go the same way for the whole
    /// run, where a loop over `events` took an indirect jump per function to a different place
    /// each time.
    #[inline(always)]
    pub(super) fn visit(&self, mut f: impl FnMut(u8)) {
        if self.tool {
            f(EV_SENSOR);
        }
        if self.object {
            f(EV_OBJECT);
            f(EV_OBJ_RELEASE);
        }
        if self.tool {
            f(EV_FWD);
            f(EV_BACK);
            f(EV_STOP_RELEASE);
        }
        if self.tool_stick {
            f(EV_TOOL_STICK);
        }
        if self.object_stick {
            f(EV_OBJ_STICK);
        }
        if self.cavitation {
            f(EV_CAVITATION);
        }
    }
}

impl Model {
    pub(super) fn log_event(&mut self, name: &str, t: f64, y: &[f64]) {
        let seg = *self.robot.current();
        let e = self.eval(t, y, &seg, &self.regime);
        let point = to_point(t, &e);
        self.log.push(EventLogEntry {
            t,
            name: name.to_string(),
            point,
        });
    }

    pub(super) fn brake_now(&mut self, t: f64, y: &[f64], ctl: &mut Control) {
        let t_stop = self.robot.brake(t);
        ctl.add_time_stop(t_stop);
        self.log_event("brake", t, y);
    }

    /// Event function `kind` at `(t, y)`, from the flange and tool kinematics `k` at that point
    /// (computed once per `events` call and shared by every event function).
    #[inline(always)]
    pub(super) fn event_value(&self, kind: u8, t: f64, y: &[f64], k: &EventKinematics) -> f64 {
        let r = &self.regime;
        let (x_r, v_r, x_t, v_t) = (k.x_r, k.v_r, k.x_t, k.v_t);
        match kind {
            EV_SENSOR => {
                if r.detected {
                    1.0
                } else {
                    x_r - x_t - self.p.s_sensor
                }
            }
            // Contacts: penetration `d`, with a hysteresis of `CONTACT_HYSTERESIS` while off
            // (a contact begins at d = 1e-14 m and ends at d = 0), so that right after either
            // event the function is strictly on its side and a touch that follows at once is
            // found (an event function that starts a step exactly at zero does not fire).
            EV_OBJECT => {
                let j = self.layout.object.unwrap_or(0);
                x_t - y[j]
                    - if r.obj_contact {
                        0.0
                    } else {
                        CONTACT_HYSTERESIS
                    }
            }
            EV_FWD => x_t - x_r - if r.fwd { 0.0 } else { CONTACT_HYSTERESIS },
            EV_BACK => x_r - x_t - self.p.stroke - if r.back { 0.0 } else { CONTACT_HYSTERESIS },
            EV_OBJ_RELEASE => {
                let j = self.layout.object.unwrap_or(0);
                let p = &self.p;
                release_value(
                    p.k_c,
                    p.chi_c,
                    v_t - y[j + 1],
                    r.obj_contact,
                    r.obj_released,
                )
            }
            EV_STOP_RELEASE => {
                let p = &self.p;
                // the forward stop's penetration rate is `-sd`, the back stop's `sd`
                let dd = if r.fwd { v_t - v_r } else { v_r - v_t };
                release_value(p.k_e, p.chi_e, dd, r.fwd || r.back, r.stop_released)
            }
            EV_TOOL_STICK => {
                if r.tool_stuck {
                    let e = self.eval(t, y, k.seg, r);
                    self.p.d * (1.0 + STICK_HYSTERESIS) - e.f_f.abs()
                } else {
                    v_r - v_t + r.tool_dir * SLIP_HYSTERESIS
                }
            }
            EV_OBJ_STICK => {
                if r.obj_stuck {
                    let e = self.eval(t, y, k.seg, r);
                    self.p.mu_n * (1.0 + STICK_HYSTERESIS) - e.f_c
                } else {
                    let j = self.layout.object.unwrap_or(0);
                    y[j + 1] + SLIP_HYSTERESIS
                }
            }
            EV_CAVITATION => self.cavitation_margin(x_r - x_t, v_r - v_t),
            _ => 1.0,
        }
    }

    /// How far event function `kind` can stray from its chord over a step of length `h` (s)
    /// whose states stray at most `dev` from theirs (`OdeSystem::event_chord_bound`). The
    /// position and speed events are affine in the state plus the robot's position (a
    /// quadratic in `t` within a step: steps never cross its kinks, which are time stops;
    /// it strays `|a_r| h^2 / 8`) or speed (linear: 0). The stuck object's function is a
    /// constant while nothing touches it. The stuck friction functions under load and the
    /// cavitation function are not affine: `None`.
    #[inline(always)]
    pub(super) fn event_straying(&self, kind: u8, h: f64, dev: &[f64]) -> Option<f64> {
        let r = &self.regime;
        let robot_x = self.robot.current().a.abs() * h * h * 0.125;
        let (tool_x, tool_v) = match self.layout.tool {
            Some(i) => (dev[i], dev[i + 1]),
            None => (robot_x, 0.0),
        };
        let object = |k: usize| self.layout.object.map_or(0.0, |j| dev[j + k]);
        match kind {
            EV_SENSOR if r.detected => Some(0.0),
            EV_SENSOR | EV_FWD | EV_BACK => Some(tool_x + robot_x),
            EV_OBJECT => Some(tool_x + object(0)),
            // `k + chi dd` is affine in the speeds (the robot's is linear within a step)
            EV_OBJ_RELEASE if r.obj_contact => Some(self.p.chi_c * (tool_v + object(1))),
            EV_STOP_RELEASE if r.fwd || r.back => Some(self.p.chi_e * tool_v),
            EV_OBJ_RELEASE | EV_STOP_RELEASE => Some(0.0),
            EV_TOOL_STICK if !r.tool_stuck => Some(tool_v),
            EV_OBJ_STICK if !r.obj_stuck => Some(object(1)),
            // stuck and untouched: `mu m_p g - F_c` with `F_c = 0`, a constant
            EV_OBJ_STICK if !r.obj_contact => Some(0.0),
            _ => None,
        }
    }

    /// Cavitation event function at stroke `s` (m) and relative speed `sd` (m/s):
    /// `p1 + dp - p_cav` (Pa) from the orifice law, whatever the regime. Kept out of line:
    /// inlined into the loop over the event functions, the compiler computes its logarithm
    /// and exponential for every scene, cavitation or not.
    #[inline(never)]
    fn cavitation_margin(&self, s: f64, sd: f64) -> f64 {
        let p = &self.p;
        // the same hysteresis idea: begins at 0, ends at +1e-12 (p10 + |p_cav|)
        let hyst = if self.regime.cavitating {
            1e-12 * (p.p10 + p.p_cav.unwrap_or(0.0).abs())
        } else {
            0.0
        };
        physics::gas_pressure(p.p10, p.v_g0, p.a_p, p.kappa, s)
            + physics::orifice_pressure_drop(p.c0, p.rho, p.a_p, p.a_o, sd)
            - p.p_cav.unwrap_or(0.0)
            - hyst
    }

    /// What event `kind` does at `(t, y)` (`y` may be changed: a part that sticks takes the
    /// speed it sticks at).
    pub(super) fn handle_event(
        &mut self,
        kind: u8,
        t: f64,
        y: &mut [f64],
        ctl: &mut Control,
    ) -> EventAction {
        // A contact event begins the contact when it is off and ends it when it is on: the
        // regime, not the sign of a value that sits on zero, decides.
        match kind {
            EV_SENSOR => {
                if self.regime.detected {
                    return EventAction::Continue;
                }
                self.detect(t, y, ctl, "sensor");
                EventAction::Restart
            }
            EV_OBJECT => self.object_contact_begins_or_ends(t, y, ctl),
            EV_OBJ_RELEASE => {
                self.regime.obj_released = !self.regime.obj_released;
                EventAction::Restart
            }
            EV_STOP_RELEASE => {
                self.regime.stop_released = !self.regime.stop_released;
                EventAction::Restart
            }
            EV_FWD => self.forward_stop_begins_or_ends(t, y),
            EV_BACK => self.back_stop_begins_or_ends(t, y),
            EV_TOOL_STICK => self.tool_sticks_or_slips(t, y),
            EV_OBJ_STICK => self.object_sticks_or_slips(t, y),
            EV_CAVITATION => {
                if self.regime.cavitating {
                    self.log_event("cavitation_end", t, y);
                    self.regime.cavitating = false;
                } else {
                    self.log_event("cavitation_begin", t, y);
                    self.regime.cavitating = true;
                }
                EventAction::Restart
            }
            _ => EventAction::Continue,
        }
    }

    /// The tool touches the object (an impact; with the rigid module, the touch is what detects
    /// the object) or leaves it.
    fn object_contact_begins_or_ends(
        &mut self,
        t: f64,
        y: &[f64],
        ctl: &mut Control,
    ) -> EventAction {
        if !self.regime.obj_contact {
            self.log_event("object_contact_begin", t, y);
            self.regime.obj_contact = true;
            self.metrics.object_impacts += 1;
            if self.p.module == Module::Rigid && !self.regime.detected {
                self.detect(t, y, ctl, "sensor");
            }
        } else {
            self.log_event("object_contact_end", t, y);
            self.regime.obj_contact = false;
        }
        self.regime.obj_released = false;
        EventAction::Restart
    }

    /// The tool hits its forward stop or leaves it.
    fn forward_stop_begins_or_ends(&mut self, t: f64, y: &[f64]) -> EventAction {
        if !self.regime.fwd {
            self.log_event("forward_stop_begin", t, y);
            self.regime.fwd = true;
            self.metrics.fwd_impacts += 1;
        } else {
            self.log_event("forward_stop_end", t, y);
            self.regime.fwd = false;
        }
        self.regime.stop_released = false;
        EventAction::Restart
    }

    /// The tool hits its back stop (the end of its stroke) or leaves it.
    fn back_stop_begins_or_ends(&mut self, t: f64, y: &[f64]) -> EventAction {
        if !self.regime.back {
            self.log_event("back_stop_begin", t, y);
            self.regime.back = true;
            self.metrics.back_impacts += 1;
            self.metrics.back_hit = true;
        } else {
            self.log_event("back_stop_end", t, y);
            self.regime.back = false;
        }
        self.regime.stop_released = false;
        EventAction::Restart
    }

    /// Dry friction on the tool: a stuck tool whose holding force passes the friction limit
    /// slips; a slipping tool whose slip speed reaches zero sticks if static friction can hold
    /// it on the robot, and otherwise slips on, the way its holding force pushes it.
    fn tool_sticks_or_slips(&mut self, t: f64, y: &mut [f64]) -> EventAction {
        let i = self.layout.tool.unwrap_or(0);
        let seg = *self.robot.current();
        if self.regime.tool_stuck {
            let e = self.eval(t, y, &seg, &self.regime);
            self.log_event("tool_slip", t, y);
            self.regime.tool_stuck = false;
            self.regime.tool_dir = e.f_f.signum();
        } else {
            // sd crossed zero: can static friction hold the tool on the robot?
            let (_, v_r, _) = seg.at(t);
            let mut trial = self.regime;
            trial.tool_stuck = true;
            let mut ys = y.to_vec();
            ys[i + 1] = v_r;
            let e = self.eval(t, &ys, &seg, &trial);
            if e.f_f.abs() <= self.p.d {
                self.log_event("tool_stick", t, y);
                y[i + 1] = v_r;
                self.regime.tool_stuck = true;
                self.regime.tool_dir = 0.0;
            } else {
                let dir = e.f_f.signum();
                if dir == self.regime.tool_dir {
                    // The slip speed touched zero and turns back: the same slip goes
                    // on, `f` is unchanged, and a restart would only find the same
                    // touch again at once (under Rodas, at every step, until the step
                    // limit: `tests/model/friction_and_contacts.rs::a_slip_that_touches_zero_and_turns_back_goes_on`).
                    return EventAction::Continue;
                }
                self.regime.tool_dir = dir;
            }
        }
        EventAction::Restart
    }

    /// Plane friction on the object: a stuck object whose contact force passes the friction
    /// limit slides; a sliding object that comes to rest sticks if friction can hold it there.
    fn object_sticks_or_slips(&mut self, t: f64, y: &mut [f64]) -> EventAction {
        let j = self.layout.object.unwrap_or(0);
        if self.regime.obj_stuck {
            self.log_event("object_slip", t, y);
            self.regime.obj_stuck = false;
            EventAction::Restart
        } else {
            let seg = *self.robot.current();
            let e = self.eval(t, y, &seg, &self.regime);
            if e.f_c <= self.p.mu_n {
                self.log_event("object_stick", t, y);
                y[j + 1] = 0.0;
                self.regime.obj_stuck = true;
                EventAction::Restart
            } else {
                EventAction::Continue
            }
        }
    }

    fn detect(&mut self, t: f64, y: &[f64], ctl: &mut Control, name: &str) {
        self.regime.detected = true;
        self.metrics.t_detect = Some(t);
        self.log_event(name, t, y);
        if self.p.dead_time > 0.0 {
            let tb = t + self.p.dead_time;
            self.pending_brake = Some(tb);
            ctl.add_time_stop(tb);
        } else {
            self.brake_now(t, y, ctl);
        }
    }
}

/// `k + chi dd` (N/m^1.5, the sign of a contact's force while it pushes) as an event function,
/// with a hysteresis of `RELEASE_HYSTERESIS k` while released, so that the function starts
/// strictly on its side after either event; 1 while the contact is off.
#[inline(always)]
fn release_value(k: f64, chi: f64, dd: f64, on: bool, released: bool) -> f64 {
    if !on {
        1.0
    } else if released {
        k + chi * dd - RELEASE_HYSTERESIS * k
    } else {
        k + chi * dd
    }
}
