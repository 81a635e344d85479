//! The tool's equilibrium on the stop that holds it and the weakly nonlinear oscillator about
//! it, from the model's own force law (Newton for the equilibrium, finite differences for the
//! coefficients); kept per robot acceleration and holding stop by the early end.

use super::StopRinging;
use crate::model::{Model, MAX_STATES};
use crate::physics::Segment;
use crate::ringing::Coefficients;

/// Equilibrium stroke (m), the holding stop's depth there (m), and the oscillator about it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Linearisation {
    pub s_eq: f64,
    pub depth: f64,
    pub coef: Coefficients,
}

impl Model {
    /// The module's force on the tool `G` (N, + forward) at stroke `s` and rate `sd`, the rest of
    /// the state as in `y` (same regime).
    pub(super) fn tool_force(&self, t: f64, y: &[f64], seg: &Segment, s: f64, sd: f64) -> f64 {
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
    pub(super) fn holding_depth(&self, s: f64) -> f64 {
        if self.regime.fwd {
            -s
        } else {
            s - self.p.stroke
        }
    }

    fn linearise(
        &self,
        t: f64,
        y: &[f64],
        seg: &Segment,
        a_r: f64,
        s: f64,
    ) -> Option<Linearisation> {
        let m = self.p.m_t;
        let h = |s: f64| self.tool_force(t, y, seg, s, 0.0) - m * a_r;
        // equilibrium: Newton from the current stroke, kept on the stop
        let mut s_eq = if self.holding_depth(s) > 0.0 {
            s
        } else {
            s - self.holding_depth(s) * 1.01 - 1e-9
        };
        let mut converged = false;
        for _ in 0..40 {
            let depth = self.holding_depth(s_eq);
            if !(depth > 0.0) {
                return None;
            }
            let ds = 1e-6 * depth;
            let slope = (h(s_eq + ds) - h(s_eq - ds)) / (2.0 * ds);
            if !(slope > 0.0) {
                return None;
            }
            let mut step = -h(s_eq) / slope;
            while self.holding_depth(s_eq + step) <= 0.0 {
                step *= 0.5;
            }
            s_eq += step;
            // converged to 1e-11 of the depth, or to what the tool's position can resolve
            // (the stroke is x_r - x_t: a stiff stop's depth, 5e-8 m for steel at 1e11
            // N/m^1.5, is resolved only to a few ulp of x_r; without this the search never
            // converges there, and every check of the tail pays 40 Newton steps again:
            // `tests::the_equilibrium_on_a_steel_stop_is_found`)
            let resolution = 4.0 * f64::EPSILON * seg.at(t).0.abs();
            if step.abs() <= (1e-11 * depth).max(resolution) {
                converged = true;
                break;
            }
        }
        let depth = self.holding_depth(s_eq);
        if !converged || !(depth > 0.0) {
            return None;
        }
        // stiffness terms by central differences of the static force, damping terms from its
        // rate dependence (linear: viscous, contact damping; quadratic: orifice)
        let d = 0.01 * depth;
        let (hp, hm, hp2, hm2, h0) = (
            h(s_eq + d),
            h(s_eq - d),
            h(s_eq + 2.0 * d),
            h(s_eq - 2.0 * d),
            h(s_eq),
        );
        let k1 = (hp - hm) / (2.0 * d);
        let k2 = (hp - 2.0 * h0 + hm) / (2.0 * d * d);
        let k3 = (hp2 - 2.0 * hp + 2.0 * hm - hm2) / (12.0 * d * d * d);
        let v = 0.01 * depth * (k1.max(0.0) / m).sqrt();
        let g = |sd: f64| self.tool_force(t, y, seg, s_eq, sd);
        let d1 = 0.5 * (g(v) - g(-v));
        let d2 = 0.5 * (g(2.0 * v) - g(-2.0 * v));
        let c = (4.0 * d1 - d2) / (2.0 * v);
        let q = ((d2 - 2.0 * d1) / (2.0 * v * v)).max(0.0);
        let coef = Coefficients {
            m,
            c,
            q,
            k1,
            k2,
            k3,
        };
        Some(Linearisation { s_eq, depth, coef })
    }
}

impl StopRinging {
    /// The equilibrium on the holding stop and the oscillator's coefficients there, for a robot
    /// segment of acceleration `a_r`. They depend on `a_r` and on which stop holds the tool only
    /// (the force law does not depend on time), so they are computed once and kept; `s` is
    /// where Newton starts.
    pub(crate) fn linearisation(
        &mut self,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        a_r: f64,
        s: f64,
    ) -> Option<Linearisation> {
        if let Some(l) = self.cached_linearisation(m, a_r) {
            return Some(l);
        }
        // a failure is not kept: Newton may succeed from a later stroke
        let l = m.linearise(t, y, seg, a_r, s)?;
        self.ringing_cache.push((a_r, m.regime.fwd, l));
        Some(l)
    }

    /// The kept linearisation for a robot segment of acceleration `a_r` on the stop that holds
    /// the tool now, if one was computed.
    pub(super) fn cached_linearisation(&self, m: &Model, a_r: f64) -> Option<Linearisation> {
        let fwd = m.regime.fwd;
        self.ringing_cache
            .iter()
            .find(|(a, f, _)| *a == a_r && *f == fwd)
            .map(|(_, _, l)| *l)
    }
}
