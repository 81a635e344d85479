//! Ringing tail: the end of a run in closed form, once only the tool's ringing is left.
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
//! frame (`ringing.rs`) about each remaining robot segment's equilibrium. Where the braking
//! robot's stop would shake the tool too much for the closed form (its new equilibrium is
//! further from the ringing than the amplitude limit allows: at tight tolerances), the ringing
//! is written in closed form only up to the stop, if that is at least a period away and the
//! ringing lightly damped, and the run is integrated again from there
//! ([`RingingTail::resume`]; its error at the stop counts as damped by the standing robot's
//! ringing until `t_end`). The coefficients are
//! taken by finite differences from the model's own force law. The final state, the robot
//! impulse (from momentum), the robot's stop on the way and the trajectory's samples come from
//! it; the energy ledger's work is exact (`W = m a_r dx_r - m [sd v_r] + m a_r ds` per segment)
//! and the dissipation closes it.

use crate::config::Module;
use crate::model::Model;
use crate::peaks::Peaks;
use crate::physics::{self, Phase, Segment};
use crate::ringing::Ringing;

mod linearisation;
use crate::Scene;
pub(crate) use linearisation::Linearisation;

/// Largest ringing amplitude handed to the closed form, as a fraction of the holding stop's
/// depth at equilibrium, at `rtol`: `0.3 sqrt(rtol / 1e-6)` within `[0.003, 0.3]`. The closed
/// form's error grows with it (`ringing.rs`); at 0.3 and rtol 1e-6 it changes the summary of the
/// paper scenes by less than the integration error itself (`examples/ringing_tail_check.rs`).
pub(crate) fn max_amplitude(rtol: f64) -> f64 {
    (0.3 * (rtol / 1e-6).sqrt()).clamp(0.003, 0.3)
}

/// The ringing about one robot segment's equilibrium.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    pub t0: f64,
    /// Equilibrium stroke (m).
    pub s_eq: f64,
    /// Depth of the holding stop at equilibrium (m).
    pub depth: f64,
    /// Robot acceleration of the segment (m/s^2).
    pub a_r: f64,
    pub ring: Ringing,
}

/// The tool's motion from the early end to the end of the run.
#[derive(Clone, Debug)]
pub(crate) struct RingingTail {
    /// One piece per robot segment left (cruising, braking, standing); in time order.
    pub pieces: Vec<Piece>,
    /// When the robot begins to brake and when it stands, if that happens inside the tail.
    pub brake: Option<f64>,
    pub stop: Option<f64>,
    /// Where the tail ends before the run does, if it does: the robot's stop, whose kink shakes
    /// the tool too much for the closed form (the new equilibrium is further from the ringing
    /// than [`max_amplitude`] allows). The run is integrated again from there (`simulate.rs`).
    pub resume: Option<f64>,
}

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

/// Error of the closed form relative to the amplitude it describes, from its initial
/// `eps = a0 / depth` and orifice damping ratio `zeta_q`: the shape's first-order error
/// (4.6e-3 eps measured in `ringing.rs`'s tests), the phase drift of the stiffness nonlinearity
/// (0.2-0.3 eps^2 rad measured on the paper's stop) and of strong orifice damping (about
/// zeta_q^2, `examples/ringing_tail_check.rs`); each doubled or more.
fn relative_error(eps: f64, zeta_q: f64) -> f64 {
    0.01 * eps + 0.5 * eps * eps + 3.0 * zeta_q * zeta_q
}

/// The earliest time (s) from now at which the closed form's predicted errors, `impulse` and
/// `energy` times what each may be, can both be within it, for the ringing `ring` that starts
/// now; `None` if either is not a number. Both fall with the amplitude `a` ([`relative_error`]
/// times `a` for the impulse, times the energy `~a^2` for the energy), no faster than their
/// steepest terms, `eps^2 a` and `zeta_q^2 a` (`a^3`) for the impulse and `eps^2 a^2` and
/// `zeta_q^2 a^2` (`a^4`) for the energy; and the amplitude falls no faster than at
/// `lambda + mu a0`. Before this time the checks cannot both pass.
fn errors_wait(ring: &Ringing, impulse: f64, energy: f64) -> Option<f64> {
    if impulse.is_nan() || energy.is_nan() {
        return None;
    }
    let shrink = (impulse.powf(1.0 / 3.0)).max(energy.powf(0.25)).max(1.0);
    Some(shrink.ln() / ring.fastest_decay_rate())
}

/// The tool on the stop that holds it: its equilibria (one per robot acceleration and holding
/// stop, kept), its rest there while the robot cruises (`resting.rs`), and the search for a
/// ringing tail (when to look again, what the closed form may leave).
pub(crate) struct StopRinging {
    /// The solver's tolerances.
    pub(crate) atol: f64,
    pub(crate) rtol: f64,
    /// `solver.ringing_tail`.
    pub(crate) ringing_enabled: bool,
    /// Largest ringing amplitude for the closed form, fraction of the stop's depth.
    pub(crate) ringing_max_amplitude: f64,
    /// Error the closed form may leave in the robot impulse, N s: rtol times the momentum scale
    /// `(m_t + m_p) v_max`.
    pub(crate) ringing_impulse_tolerance: f64,
    /// No ringing-tail check before this time.
    pub(crate) next_ringing_check: f64,
    /// Linearisations about the stop's equilibrium, by robot acceleration and holding stop.
    pub(crate) ringing_cache: Vec<(f64, bool, Linearisation)>,
}

impl StopRinging {
    pub fn new(scene: &Scene) -> StopRinging {
        let m_p = if scene.object.enabled {
            scene.object.mass
        } else {
            0.0
        };
        StopRinging {
            atol: scene.solver.atol,
            rtol: scene.solver.rtol,
            ringing_enabled: scene.solver.ringing_tail,
            ringing_max_amplitude: max_amplitude(scene.solver.rtol),
            ringing_impulse_tolerance: scene.solver.rtol
                * (scene.tool.mass + m_p)
                * scene.robot.approach_speed,
            next_ringing_check: 0.0,
            ringing_cache: Vec::new(),
        }
    }
}

impl RingingTail {
    /// A bound of the error the closed form leaves in the robot impulse at `t_end`, N s: the
    /// tool's momentum error `m_t w0 e a(t_end)` from each piece's relative error `e`, carried
    /// through the later pieces with their decay.
    pub fn impulse_error(&self, m_t: f64, t_end: f64) -> f64 {
        let mut err = 0.0;
        let mut w0 = 0.0;
        for (k, pc) in self.pieces.iter().enumerate() {
            let t1 = self.pieces.get(k + 1).map_or(t_end, |n| n.t0);
            let r = &pc.ring;
            let eps = r.a0 / pc.depth;
            let zeta_q = r.orifice_damping_ratio();
            err = err * (-r.decay_rate() * (t1 - pc.t0)).exp()
                + relative_error(eps, zeta_q) * r.amplitude(t1);
            w0 = r.w0;
        }
        m_t * w0 * err
    }

    /// Stroke `s` (m) and its rate `sd` (m/s) at `t` after the early end.
    pub fn stroke_at(&self, t: f64) -> (f64, f64) {
        let p = self
            .pieces
            .iter()
            .rev()
            .find(|p| t >= p.t0)
            .unwrap_or(&self.pieces[0]);
        let (u, v) = p.ring.state(t);
        (p.s_eq + u, v)
    }
}

impl StopRinging {
    /// The ringing through `(s, sd)` at `t` about the equilibrium of a robot segment with
    /// acceleration `a_r`. `Err(Some(wait))` if it rings too strongly for the closed form now,
    /// with the time (s) its amplitude needs to decay to the limit at the largest decay rate it
    /// can have, `lambda + mu a` (linear and orifice damping; the orifice's share falls with the
    /// amplitude, so the real wait is longer); `Err(None)` if the tool has no equilibrium on
    /// its stop or the closed form does not describe it.
    #[allow(clippy::too_many_arguments)]
    fn ringing_piece(
        &mut self,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        a_r: f64,
        s: f64,
        sd: f64,
    ) -> Result<Piece, Option<f64>> {
        let lin = self.linearisation(m, t, y, seg, a_r, s).ok_or(None)?;
        let c = &lin.coef;
        let (u0, max) = (s - lin.s_eq, self.ringing_max_amplitude * lin.depth);
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

    /// The tool's ringing from `(t, y)` to the end of the run, if the rest of the run may be
    /// written as that (see the module docs); `peaks` are the run's so far, which the tail must
    /// not change.
    pub(crate) fn try_ringing_tail(
        &mut self,
        m: &Model,
        peaks: &Peaks,
        t: f64,
        y: &[f64],
    ) -> Option<RingingTail> {
        let p = &m.p;
        let r = &m.regime;
        let seg = *m.robot.current();
        let cruising_to_brake = seg.phase == Phase::Cruising && m.pending_brake.is_some();
        let quiet = self.ringing_enabled
            && t >= self.next_ringing_check
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
                || (m.cruising_to_end() && m.object_outruns(y, seg.at(t).1)));
        if !quiet {
            return None;
        }
        let (x_r, v_r, a_r) = seg.at(t);
        let i = m.layout.tool.unwrap_or(0);
        let (s, sd) = (x_r - y[i], v_r - y[i + 1]);
        let first = match self.ringing_piece(m, t, y, &seg, a_r, s, sd) {
            Ok(piece) => piece,
            Err(wait) => {
                // look again once the ringing may have decayed enough: when its amplitude can
                // first be small enough, and at least a tenth of a period on
                // (or right after the robot's next kink: a new equilibrium, a new amplitude)
                let tenth = 0.1 * self.ringing_period_guess(m);
                let kink = match seg.phase {
                    Phase::Braking => seg.stop_time(),
                    _ => m.pending_brake.unwrap_or(f64::INFINITY),
                };
                let next = t + wait.map_or(tenth, |w| w.max(tenth));
                self.next_ringing_check = next.min(kink.max(t + tenth));
                return None;
            }
        };
        // the robot's segments still to come: braking at the pending brake time, standing at
        // the end of braking
        let mut tail = RingingTail {
            pieces: vec![first],
            brake: None,
            stop: None,
            resume: None,
        };
        let mut last = seg;
        // what the ringing integrated after a tail that ends at the robot's stop leaves of the
        // closed form's error there at `t_end`
        let mut resumed_decay = 1.0;
        if cruising_to_brake {
            let tb = m.pending_brake.unwrap_or(f64::INFINITY);
            if tb < m.t_end {
                last = seg.braking_from(tb, m.robot.a_brake);
                if !self.extend_tail(m, &mut tail, y, &last) {
                    return None;
                }
                tail.brake = Some(tb);
            }
        }
        if last.phase == Phase::Braking {
            let t_stop = last.stop_time();
            if t_stop < m.t_end {
                let stopped = last.stopped_at(t_stop);
                if self.extend_tail(m, &mut tail, y, &stopped) {
                    tail.stop = Some(t_stop);
                    last = stopped;
                } else {
                    // the closed form as far as the robot's stop, where the integration
                    // resumes, if the braking robot is left alone long enough to pay for the
                    // restart, and the ringing is as lightly damped as where the error model
                    // was measured (at a damping ratio of 0.11 a design point's tail up to the
                    // stop left an energy residual of 7.4 rtol)
                    // (`tests/early_end.rs::a_tail_up_to_the_robots_stop_equals_running_through_it`)
                    let long = t_stop - t >= RESUME_AFTER_PERIODS * self.ringing_period_guess(m);
                    let light = tail.pieces[0].ring.zeta <= PREDICTED_DAMPING;
                    if !(seg.phase == Phase::Braking && long && light) {
                        return None;
                    }
                    tail.resume = Some(t_stop);
                    // the closed form's error at the stop seeds the integrated ringing about
                    // the standing robot's equilibrium, which damps it by its linear decay
                    // rate until the run ends
                    let (s_stop, _) = tail.stroke_at(t_stop);
                    let lin = self.linearisation(m, t_stop, y, &stopped, stopped.a, s_stop)?;
                    resumed_decay = (-lin.coef.linear_decay() * (m.t_end - t_stop)).exp();
                }
            }
        }
        // the closed form's predicted errors, as multiples of what it may leave: both shrink with
        // the ringing's amplitude, so while one is too large, look again once the amplitude can
        // have shrunk enough (`errors_wait`), where the prediction holds; elsewhere a period on
        // (a tail that ends at the robot's stop leaves its error there to the integrated rest of
        // the run, which damps it)
        let impulse = tail.impulse_error(m.p.m_t, tail.resume.unwrap_or(m.t_end)) * resumed_decay
            / self.ringing_impulse_tolerance;
        let energy = self.energy_error_excess(m, &tail, t, y);
        if !(impulse <= 1.0 && energy <= 1.0) {
            let period = self.ringing_period_guess(m);
            let lightly_damped = tail.pieces.iter().all(|p| p.ring.zeta <= PREDICTED_DAMPING);
            let wait = match errors_wait(&tail.pieces[0].ring, impulse, energy) {
                Some(w) if lightly_damped => w,
                _ => period,
            };
            // (at least a quarter period on: a look costs about two steps' work, and where a
            // robot kink's shift of the equilibrium rather than the amplitude holds the errors
            // up, they do not fall as fast as `errors_wait` allows)
            self.next_ringing_check = t + wait.max(0.25 * period);
            return None;
        }
        if !tail_changes_nothing(m, peaks, t, y, &seg, &last, &tail) {
            self.next_ringing_check = t + self.ringing_period_guess(m);
            return None;
        }
        Some(tail)
    }

    /// With the energy ledger on, its residual over the tail checks the closed form against the
    /// force law (`tail.rs`, `Tail::dissipation`): the tail is taken only where the closed
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
    fn extend_tail(
        &mut self,
        m: &Model,
        tail: &mut RingingTail,
        y: &[f64],
        next: &Segment,
    ) -> bool {
        let (s, sd) = tail.stroke_at(next.t0);
        match self.ringing_piece(m, next.t0, y, next, next.a, s, sd) {
            Ok(piece) => {
                tail.pieces.push(piece);
                true
            }
            Err(_) => {
                self.next_ringing_check = next.t0;
                false
            }
        }
    }

    /// A period of the tool on its stop (s), for spacing the checks: from the linearisation
    /// about the current robot segment's equilibrium on the holding stop when there is one,
    /// else from the stop's stiffness at a depth of 0.1 mm.
    fn ringing_period_guess(&self, m: &Model) -> f64 {
        let k = self
            .cached_linearisation(m, m.robot.current().a)
            .map(|l| l.coef.k1)
            .filter(|&k1| k1 > 0.0)
            .unwrap_or(1.5 * m.p.k_e * (1e-4f64).sqrt());
        2.0 * std::f64::consts::PI * (m.p.m_t / k).sqrt()
    }
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

#[cfg(test)]
mod tests {
    use super::{errors_wait, StopRinging};
    use crate::config::Scene;
    use crate::model::Model;
    use crate::ringing::{Coefficients, Ringing};

    /// `errors_wait` against the amplitude law it bounds: an impulse error `x` times its limit
    /// needs the amplitude `x^(1/3)` times smaller, an energy error `x^(1/4)`; at the wait the
    /// closed form's amplitude has shrunk by exactly that with linear damping alone, and by no
    /// more with the orifice's (whose share falls with the amplitude).
    #[test]
    fn a_declined_tail_is_looked_at_again_when_its_errors_can_first_pass() {
        let (k, depth) = (0.6e6_f64, 1.64e-4_f64);
        for (q, eps) in [(0.0, 0.3), (66.0, 0.3), (3000.0, 0.02)] {
            let c = Coefficients {
                m: 0.048,
                c: 1.35e6 * depth * depth.sqrt() + 0.5,
                q,
                k1: 1.5 * k * depth.sqrt(),
                k2: 0.0,
                k3: 0.0,
            };
            let r = Ringing::through(&c, 0.0, eps * depth, 0.0).unwrap();
            for (impulse, energy, shrink) in [
                (8.0, 0.5, 2.0),
                (0.5, 81.0, 3.0),
                (8.0, 81.0, 3.0),
                (27.0, 16.0, 3.0),
            ] {
                let w = errors_wait(&r, impulse, energy).unwrap();
                let shrunk = r.a0 / r.amplitude(w);
                if q == 0.0 {
                    assert!(
                        (shrunk / shrink - 1.0).abs() < 1e-12,
                        "q 0: {shrunk} vs {shrink}"
                    );
                } else {
                    assert!(
                        shrunk > 1.0 && shrunk <= shrink * (1.0 + 1e-12),
                        "q {q}: {shrunk} vs {shrink}"
                    );
                }
            }
            assert_eq!(errors_wait(&r, 0.5, 1.0), Some(0.0));
            assert_eq!(errors_wait(&r, f64::NAN, 0.5), None);
            assert_eq!(errors_wait(&r, 0.5, f64::NAN), None);
        }
    }

    /// The tool resting on its forward stop at the preload, with the robot cruising: the
    /// equilibrium on the stop is found for a paper-like stop and for a steel one, whose depth
    /// (5e-8 m at 1e11 N/m^1.5) only a few ulp of the flange's position resolve.
    #[test]
    fn the_equilibrium_on_a_steel_stop_is_found() {
        for stiffness in ["6e5", "1e11", "1e12"] {
            let mut scene = Scene::default();
            scene.set_from_str("stops.stiffness", stiffness).unwrap();
            let m = Model::new(&scene);
            let mut stop = StopRinging::new(&scene);
            let y = m.y0.clone();
            let t = 0.05;
            let seg = *m.robot.current();
            let (x_r, _, a_r) = seg.at(t);
            // the tool where the preload left it, relative to the flange
            let i = m.layout.tool.unwrap();
            let s0 = -y[i];
            let mut z = y.clone();
            z[i] = x_r - s0;
            let l = stop.linearisation(&m, t, &z, &seg, a_r, s0);
            assert!(l.is_some(), "stops.stiffness = {stiffness}: no equilibrium");
        }
    }
}
