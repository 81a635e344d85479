//! When the ringing tail is taken (`solver.ringing_tail`): the end of a run in closed form, once
//! only the tool's ringing on its stop is left.
//!
//! After an impact the tool returns onto the end-stop that holds it and rings there, lightly
//! damped (paper scene: ~78 Hz, damping ratio ~0.07), until `t_end`. An explicit method follows
//! each period with ~15 steps: 300 of the paper scene's 360 steps. Once
//!
//! - the robot brakes, stands, cruises toward a brake already scheduled, or cruises on with no
//!   brake before `t_end` (its motion to `t_end` is known; the sensor, if it has not switched,
//!   stays out of the ringing's reach),
//! - the object can never be touched again (absent; or out of contact, free, at least as fast as
//!   the robot and ahead of anything the tool can reach; or resting on the plane out of reach),
//! - the tool is held by exactly one stop, without dry friction, and rings about that robot
//!   segment's equilibrium with an amplitude below [`max_amplitude`] of the stop's depth and
//!   weak orifice damping, small enough that no summary value can change (no new peak of
//!   `|F_r|` or stroke, the stop contact never opens, no cavitation),
//! - the closed form's predicted error in the robot impulse at `t_end`
//!   ([`RingingTail::impulse_error`]) is below `rtol (m_t + m_p) v_max`,
//!
//! the run ends and the tool's motion is written as a weakly nonlinear oscillator in the robot's
//! frame (`ringing.rs`; the tail itself and its error model: `ringing_tail.rs`) about each
//! remaining robot segment's equilibrium. Where the braking
//! robot's stop would shake the tool too much for the closed form (its new equilibrium is
//! further from the ringing than the amplitude limit allows: at tight tolerances), the ringing
//! is written in closed form only up to the stop, if that is at least a period away and the
//! ringing lightly damped, and the run is integrated again from there
//! ([`RingingTail::resume`]; its error at the stop counts as damped by the standing robot's
//! ringing until `t_end`). The coefficients are taken by finite differences from the model's
//! own force law (`linearisation.rs`). The final state, the robot
//! impulse (from momentum), the robot's stop on the way and the trajectory's samples come from
//! it; the energy ledger's work is exact (`W = m a_r dx_r - m [sd v_r] + m a_r ds` per segment)
//! and the dissipation closes it (`ledger.rs`).
//!
//! [`RingingSearch::try_tail`] is called at every step that no other tail ends; it looks again
//! only where the ringing can first have become small enough, so most steps pay one comparison.

use super::linearisation::Linearisations;
use super::ringing::Ringing;
use super::ringing_tail::{errors_wait, max_amplitude, relative_error, Piece, RingingTail};
use super::{cruising_to_end, object_outruns};
use crate::config::Module;
use crate::model::Model;
use crate::peaks::Peaks;
use crate::physics::{self, Phase, Segment};
use crate::Scene;

/// The closed form's predicted energy error allowed, in rtol of the energy ledger's scale.
const ENERGY_ERROR: f64 = 3.0;

/// A tail that ends at the robot's stop, where the integration resumes, is taken only if it
/// spans at least this many of the ringing's periods: a restart costs the integrator a few
/// steps (its first step size and the steps that grow it), a period about fifteen.
const RESUME_AFTER_PERIODS: f64 = 1.0;

/// Largest equivalent damping ratio of the orifice's quadratic damping at the initial amplitude.
const MAX_ORIFICE_DAMPING: f64 = 0.1;

/// Largest damping ratio of the ringing for which a tail declined for its predicted errors is
/// looked at again as soon as they can be within their limits ([`errors_wait`]); more damped
/// ringing is looked at again a period later. [`relative_error`] was measured on lightly damped
/// ringing (the paper's stops: 0.07); it leaves out how the stop's damping grows with the
/// depth, which counts when that damping is strong: on a design point ringing at 0.49 a tail
/// taken as soon as its predicted energy error was 0.92 of the limit left a residual of 36
/// rtol, 12 times the limit, where the tail taken a period later left 0.5 rtol. Up to 0.1
/// the design space's largest residuals are those of before (above 1e-5: the same 14 runs,
/// none from the tail; `docs/levers.md`).
const PREDICTED_DAMPING: f64 = 0.1;

/// The search for a ringing tail: what the closed form may leave, and when to look again.
pub(super) struct RingingSearch {
    /// The solver's relative tolerance.
    rtol: f64,
    /// `solver.ringing_tail`.
    enabled: bool,
    /// Largest ringing amplitude for the closed form, fraction of the stop's depth.
    max_amplitude: f64,
    /// Error the closed form may leave in the robot impulse, N s: rtol times the momentum scale
    /// `(m_t + m_p) v_max`.
    impulse_tolerance: f64,
    /// No ringing-tail check before this time.
    next_check: f64,
}

impl RingingSearch {
    pub fn new(scene: &Scene) -> RingingSearch {
        let m_p = if scene.object.enabled {
            scene.object.mass
        } else {
            0.0
        };
        RingingSearch {
            rtol: scene.solver.rtol,
            enabled: scene.solver.ringing_tail,
            max_amplitude: max_amplitude(scene.solver.rtol),
            impulse_tolerance: scene.solver.rtol
                * (scene.tool.mass + m_p)
                * scene.robot.approach_speed,
            next_check: 0.0,
        }
    }

    /// The tool's ringing from `(t, y)` to the end of the run, if the rest of the run may be
    /// written as that (see the module docs); `peaks` are the run's so far, which the tail must
    /// not change. `lins` are the tool's equilibria on its stop, kept.
    pub fn try_tail(
        &mut self,
        lins: &mut Linearisations,
        m: &Model,
        peaks: &Peaks,
        t: f64,
        y: &[f64],
    ) -> Option<RingingTail> {
        let seg = *m.robot.current();
        if !self.may_ring(m, &seg, t, y) {
            return None;
        }
        let (x_r, v_r, a_r) = seg.at(t);
        let i = m.layout.tool.unwrap_or(0);
        let (s, sd) = (x_r - y[i], v_r - y[i + 1]);
        let first = match self.piece(lins, m, t, y, &seg, a_r, s, sd) {
            Ok(piece) => piece,
            Err(wait) => {
                // look again once the ringing may have decayed enough: when its amplitude can
                // first be small enough, and at least a tenth of a period on
                // (or right after the robot's next kink: a new equilibrium, a new amplitude)
                let tenth = 0.1 * period_guess(lins, m);
                let kink = match seg.phase {
                    Phase::Braking => seg.stop_time(),
                    _ => m.pending_brake.unwrap_or(f64::INFINITY),
                };
                let next = t + wait.map_or(tenth, |w| w.max(tenth));
                self.next_check = next.min(kink.max(t + tenth));
                return None;
            }
        };
        let mut tail = RingingTail {
            pieces: vec![first],
            brake: None,
            stop: None,
            resume: None,
        };
        let (last, resumed_decay) = self.follow_the_robot(lins, m, t, y, &seg, &mut tail)?;
        if !self.errors_within_limits(lins, m, t, y, &tail, resumed_decay) {
            return None;
        }
        if !tail_changes_nothing(m, peaks, t, y, &seg, &last, &tail) {
            self.next_check = t + period_guess(lins, m);
            return None;
        }
        Some(tail)
    }

    /// Whether the run is in a state the ringing tail may end (the conditions of the module
    /// docs that the state shows, before any physics), and a check is due.
    fn may_ring(&self, m: &Model, seg: &Segment, t: f64, y: &[f64]) -> bool {
        let p = &m.p;
        let r = &m.regime;
        let cruising_to_brake = seg.phase == Phase::Cruising && m.pending_brake.is_some();
        self.enabled
            && t >= self.next_check
            && matches!(p.module, Module::Hydraulic | Module::Bistable)
            && m.layout.tool.is_some()
            && m.layout.liquid.is_none()
            && p.d == 0.0
            && !r.tool_stuck
            && !r.cavitating
            && !r.obj_contact
            && (r.fwd != r.back)
            && !r.stop_released
            && (matches!(seg.phase, Phase::Braking | Phase::Stopped)
                || cruising_to_brake
                || (cruising_to_end(m) && object_outruns(m, y, seg.at(t).1)))
    }

    /// The ringing through `(s, sd)` at `t` about the equilibrium of a robot segment with
    /// acceleration `a_r`. `Err(Some(wait))` if it rings too strongly for the closed form now,
    /// with the time (s) its amplitude needs to decay to the limit at the largest decay rate it
    /// can have, `lambda + mu a` (linear and orifice damping; the orifice's share falls with the
    /// amplitude, so the real wait is longer); `Err(None)` if the tool has no equilibrium on
    /// its stop or the closed form does not describe it.
    #[allow(clippy::too_many_arguments)]
    fn piece(
        &self,
        lins: &mut Linearisations,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        a_r: f64,
        s: f64,
        sd: f64,
    ) -> Result<Piece, Option<f64>> {
        let lin = lins.linearisation(m, t, y, seg, a_r, s).ok_or(None)?;
        let c = &lin.coef;
        let (u0, max) = (s - lin.s_eq, self.max_amplitude * lin.depth);
        if !(c.k1 > 0.0) {
            return Err(None);
        }
        // time for amplitude `a` to decay to `limit`
        let wait = |a: f64, limit: f64| {
            let rate = c.linear_decay() + c.orifice_decay() * a;
            (rate > 0.0).then(|| (a / limit).ln() / rate)
        };
        // the linear amplitude first (it may exceed the closed form's by up to 30 %): most
        // checks end here, cheaply
        let a_lin = u0.hypot((sd + c.linear_decay() * u0) / c.w0());
        if !(a_lin <= 1.3 * max) {
            return Err(wait(a_lin, 1.3 * max));
        }
        let ring = Ringing::through(c, t, u0, sd).ok_or(None)?;
        // small amplitude, and the orifice's damping weak too (the averaging assumes both)
        if !(ring.reach() <= max) {
            return Err(wait(ring.reach(), max));
        }
        if !(ring.orifice_damping_ratio() <= MAX_ORIFICE_DAMPING) {
            return Err(None);
        }
        Ok(Piece {
            t0: t,
            s_eq: lin.s_eq,
            depth: lin.depth,
            a_r,
            ring,
        })
    }

    /// Continue `tail` (its first piece in the robot segment `seg`, at `t`) through the robot's
    /// segments still to come: braking at the pending brake time, standing at the end of
    /// braking. Returns the last segment, and what the ringing integrated after a tail that
    /// ends at the robot's stop leaves of the closed form's error there at `t_end` (1 for a
    /// tail to `t_end`); `None` if no tail may be taken.
    fn follow_the_robot(
        &mut self,
        lins: &mut Linearisations,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        tail: &mut RingingTail,
    ) -> Option<(Segment, f64)> {
        let cruising_to_brake = seg.phase == Phase::Cruising && m.pending_brake.is_some();
        let mut last = *seg;
        // what the ringing integrated after a tail that ends at the robot's stop leaves of the
        // closed form's error there at `t_end`
        let mut resumed_decay = 1.0;
        if cruising_to_brake {
            let tb = m.pending_brake.unwrap_or(f64::INFINITY);
            if tb < m.t_end {
                last = seg.braking_from(tb, m.robot.a_brake);
                if !self.extend(lins, m, tail, y, &last) {
                    return None;
                }
                tail.brake = Some(tb);
            }
        }
        if last.phase == Phase::Braking {
            let t_stop = last.stop_time();
            if t_stop < m.t_end {
                let stopped = last.stopped_at(t_stop);
                if self.extend(lins, m, tail, y, &stopped) {
                    tail.stop = Some(t_stop);
                    last = stopped;
                } else {
                    // the closed form as far as the robot's stop, where the integration
                    // resumes, if the braking robot is left alone long enough to pay for the
                    // restart, and the ringing is as lightly damped as where the error model
                    // was measured (at a damping ratio of 0.11 a design point's tail up to the
                    // stop left an energy residual of 7.4 rtol)
                    // (`tests/model/early_end.rs::a_tail_up_to_the_robots_stop_equals_running_through_it`)
                    let long = t_stop - t >= RESUME_AFTER_PERIODS * period_guess(lins, m);
                    let light = tail.pieces[0].ring.zeta <= PREDICTED_DAMPING;
                    if !(seg.phase == Phase::Braking && long && light) {
                        return None;
                    }
                    tail.resume = Some(t_stop);
                    // the closed form's error at the stop seeds the integrated ringing about
                    // the standing robot's equilibrium, which damps it by its linear decay
                    // rate until the run ends
                    let (s_stop, _) = tail.stroke_at(t_stop);
                    let lin = lins.linearisation(m, t_stop, y, &stopped, stopped.a, s_stop)?;
                    resumed_decay = (-lin.coef.linear_decay() * (m.t_end - t_stop)).exp();
                }
            }
        }
        Some((last, resumed_decay))
    }

    /// Whether the closed form's predicted errors are within what it may leave; if not, no
    /// check before they can be. `resumed_decay`: what the integrated rest of the run leaves
    /// of the error at the robot's stop, for a tail that ends there.
    fn errors_within_limits(
        &mut self,
        lins: &Linearisations,
        m: &Model,
        t: f64,
        y: &[f64],
        tail: &RingingTail,
        resumed_decay: f64,
    ) -> bool {
        // the closed form's predicted errors, as multiples of what it may leave: both shrink with
        // the ringing's amplitude, so while one is too large, look again once the amplitude can
        // have shrunk enough (`errors_wait`), where the prediction holds; elsewhere a period on
        // (a tail that ends at the robot's stop leaves its error there to the integrated rest of
        // the run, which damps it)
        let impulse = tail.impulse_error(m.p.m_t, tail.resume.unwrap_or(m.t_end)) * resumed_decay
            / self.impulse_tolerance;
        let energy = self.energy_error_excess(m, tail, t, y);
        if !(impulse <= 1.0 && energy <= 1.0) {
            let period = period_guess(lins, m);
            let lightly_damped = tail.pieces.iter().all(|p| p.ring.zeta <= PREDICTED_DAMPING);
            let wait = match errors_wait(&tail.pieces[0].ring, impulse, energy) {
                Some(w) if lightly_damped => w,
                _ => period,
            };
            // (at least a quarter period on: a look costs about two steps' work, and where a
            // robot kink's shift of the equilibrium rather than the amplitude holds the errors
            // up, they do not fall as fast as `errors_wait` allows)
            self.next_check = t + wait.max(0.25 * period);
            return false;
        }
        true
    }

    /// With the energy ledger on, its residual over the tail checks the closed form against the
    /// force law (`ledger.rs`, `dissipation`): the tail is taken only where the closed
    /// form's predicted energy error, its relative error times the ringing's energy
    /// `k1 a0^2 / 2` summed over the pieces, is within [`ENERGY_ERROR`] rtol of the ledger's
    /// scale at `(t, y)`. The error measured on the paper scenes and the design space is 0.4-2.5
    /// times that prediction. Returns the prediction over that limit (0 without the ledger).
    fn energy_error_excess(&self, m: &Model, tail: &RingingTail, t: f64, y: &[f64]) -> f64 {
        let Some(scale) = crate::ledger::scale(m, t, y) else {
            return 0.0;
        };
        let predicted: f64 = tail
            .pieces
            .iter()
            .map(|pc| {
                let r = &pc.ring;
                relative_error(r.a0 / pc.depth, r.orifice_damping_ratio()) * r.energy(m.p.m_t, r.a0)
            })
            .sum();
        predicted / (ENERGY_ERROR * self.rtol * scale)
    }

    /// Continue the tail into the robot segment `next` (from its start); false, and no check
    /// before that segment begins, if the kink shakes the tool too much for the closed form.
    fn extend(
        &mut self,
        lins: &mut Linearisations,
        m: &Model,
        tail: &mut RingingTail,
        y: &[f64],
        next: &Segment,
    ) -> bool {
        let (s, sd) = tail.stroke_at(next.t0);
        match self.piece(lins, m, next.t0, y, next, next.a, s, sd) {
            Ok(piece) => {
                tail.pieces.push(piece);
                true
            }
            Err(_) => {
                self.next_check = next.t0;
                false
            }
        }
    }
}

/// A period of the tool on its stop (s), for spacing the checks: from the linearisation
/// about the current robot segment's equilibrium on the holding stop when there is one,
/// else from the stop's stiffness at a depth of 0.1 mm.
fn period_guess(lins: &Linearisations, m: &Model) -> f64 {
    let k = lins
        .cached(m, m.robot.current().a)
        .map(|l| l.coef.k1)
        .filter(|&k1| k1 > 0.0)
        .unwrap_or(1.5 * m.p.k_e * (1e-4f64).sqrt());
    2.0 * std::f64::consts::PI * (m.p.m_t / k).sqrt()
}

/// No summary value can change during the tail: `|F_r|` stays below its peak, the stroke
/// below its maximum, the stop contact stays closed, the object is never reached, no
/// cavitation.
fn tail_changes_nothing(
    m: &Model,
    peaks: &Peaks,
    t: f64,
    y: &[f64],
    seg: &Segment,
    last: &Segment,
    tail: &RingingTail,
) -> bool {
    let p = &m.p;
    let mut s_lo = f64::INFINITY;
    for pc in &tail.pieces {
        let reach = 1.5 * pc.ring.reach();
        let speed = 1.5 * pc.ring.speed_bound();
        let depth = m.holding_depth(pc.s_eq);
        // (below the largest stroke is also below the sensor's threshold when the sensor
        // has not switched yet, as while the robot cruises on)
        if !(reach < 0.5 * depth) || !(pc.s_eq + reach < peaks.max_stroke) {
            return false;
        }
        // |F_r| = |G| = |m a_r + K1 u + ...| (no object contact)
        let w0 = pc.ring.w0;
        let f_bound =
            p.m_t * (pc.a_r.abs() + 1.5 * w0 * w0 * reach + 2.0 * pc.ring.zeta * w0 * speed);
        if !(f_bound < 0.9 * peaks.peak_fr.abs()) {
            return false;
        }
        if let Some(p_cav) = p.p_cav {
            let p1 = physics::gas_pressure(p.p10, p.v_g0, p.a_p, p.kappa, pc.s_eq - reach);
            let dp = physics::orifice_pressure_drop(p.c0, p.rho, p.a_p, p.a_o, speed);
            if !(p1 - dp.abs() > p_cav) {
                return false;
            }
        }
        s_lo = s_lo.min(pc.s_eq - reach);
    }
    match m.layout.object {
        None => true,
        Some(j) => {
            let (x_r, v_r, _) = seg.at(t);
            // where the robot comes to rest (or is at t_end if it never does)
            let x_r_final = match last.phase {
                Phase::Braking => last.at(last.stop_time()).0,
                _ => last.at(m.t_end).0,
            };
            let (x_p, v_p) = (y[j], y[j + 1]);
            let free_and_away = p.mu_n == 0.0 && v_p >= v_r.max(0.0) && x_p > x_r - s_lo;
            let resting = (p.mu_n == 0.0 && v_p >= 0.0) || m.regime.obj_stuck;
            free_and_away || (resting && x_p > x_r_final - s_lo)
        }
    }
}
