//! The ringing tail: the tool's ringing on its stop from the early end on, written as a weakly
//! nonlinear oscillator in the robot's frame (`ringing.rs`) about each remaining robot
//! segment's equilibrium (one [`Piece`] per segment: cruising, braking, standing), and the
//! closed form's predicted error.
//!
//! The error model: relative to the amplitude it describes, the closed form errs by its shape's
//! first-order error, the phase drift of the stiffness nonlinearity and that of strong orifice
//! damping ([`relative_error`], each term measured and doubled or more); the robot impulse
//! errs by the tool's momentum error that leaves at `t_end` ([`RingingTail::impulse_error`]).
//! Both fall with the amplitude, which bounds how soon a tail declined for them can pass
//! ([`errors_wait`]). When a tail is taken: `ringing_search.rs`.

use super::ringing::Ringing;

/// Largest ringing amplitude handed to the closed form, as a fraction of the holding stop's
/// depth at equilibrium, at `rtol`: `0.3 sqrt(rtol / 1e-6)` within `[0.003, 0.3]`. The closed
/// form's error grows with it (`ringing.rs`); at 0.3 and rtol 1e-6 it changes the summary of the
/// paper scenes by less than the integration error itself (the study binary `ringing_tail_check`,
/// `lab/studies/src/bin/ringing_tail_check.rs`).
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

/// Error of the closed form relative to the amplitude it describes, from its initial
/// `eps = a0 / depth` and orifice damping ratio `zeta_q`: the shape's first-order error
/// (4.6e-3 eps measured in `ringing.rs`'s tests), the phase drift of the stiffness nonlinearity
/// (0.2-0.3 eps^2 rad measured on the paper's stop) and of strong orifice damping (about
/// zeta_q^2, `lab/studies/src/bin/ringing_tail_check.rs`); each doubled or more.
pub(super) fn relative_error(eps: f64, zeta_q: f64) -> f64 {
    0.01 * eps + 0.5 * eps * eps + 3.0 * zeta_q * zeta_q
}

/// The earliest time (s) from now at which the closed form's predicted errors, `impulse` and
/// `energy` times what each may be, can both be within it, for the ringing `ring` that starts
/// now; `None` if either is not a number. Both fall with the amplitude `a` ([`relative_error`]
/// times `a` for the impulse, times the energy `~a^2` for the energy), no faster than their
/// steepest terms, `eps^2 a` and `zeta_q^2 a` (`a^3`) for the impulse and `eps^2 a^2` and
/// `zeta_q^2 a^2` (`a^4`) for the energy; and the amplitude falls no faster than at
/// `lambda + mu a0`. Before this time the checks cannot both pass.
pub(super) fn errors_wait(ring: &Ringing, impulse: f64, energy: f64) -> Option<f64> {
    if impulse.is_nan() || energy.is_nan() {
        return None;
    }
    let shrink = (impulse.powf(1.0 / 3.0)).max(energy.powf(0.25)).max(1.0);
    Some(shrink.ln() / ring.fastest_decay_rate())
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

#[cfg(test)]
mod tests {
    use super::errors_wait;
    use crate::early_end::ringing::{Coefficients, Ringing};
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
}
