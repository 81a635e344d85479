//! The tool's equilibrium on the stop that holds it and the weakly nonlinear oscillator about
//! it, from the model's own force law (Newton for the equilibrium, finite differences for the
//! coefficients); kept per robot acceleration and holding stop ([`Linearisations`]), which the
//! riding and the ringing tails share.
//!
//! The linearisation is early-end logic and lives here, as a function of the model; what it
//! asks of the model is physics, which lives in `model/` (`Model::tool_force`, the module's
//! force on the tool at a given stroke and rate, and `Model::holding_depth`).

use super::ringing::Coefficients;
use crate::model::Model;
use crate::physics::Segment;

/// Equilibrium stroke (m), the holding stop's depth there (m), and the oscillator about it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Linearisation {
    pub s_eq: f64,
    pub depth: f64,
    pub coef: Coefficients,
}

/// The linearisations about the tool's equilibrium on its stop, by robot acceleration and
/// holding stop, kept for the run.
#[derive(Default)]
pub(super) struct Linearisations(Vec<(f64, bool, Linearisation)>);

impl Linearisations {
    /// The equilibrium on the holding stop and the oscillator's coefficients there, for a robot
    /// segment of acceleration `a_r`. They depend on `a_r` and on which stop holds the tool only
    /// (the force law does not depend on time), so they are computed once and kept; `s` is
    /// where Newton starts.
    pub fn linearisation(
        &mut self,
        m: &Model,
        t: f64,
        y: &[f64],
        seg: &Segment,
        a_r: f64,
        s: f64,
    ) -> Option<Linearisation> {
        if let Some(l) = self.cached(m, a_r) {
            return Some(l);
        }
        // a failure is not kept: Newton may succeed from a later stroke
        let l = linearise(m, t, y, seg, a_r, s)?;
        self.0.push((a_r, m.regime.fwd, l));
        Some(l)
    }

    /// The kept linearisation for a robot segment of acceleration `a_r` on the stop that holds
    /// the tool now, if one was computed.
    pub fn cached(&self, m: &Model, a_r: f64) -> Option<Linearisation> {
        let fwd = m.regime.fwd;
        self.0
            .iter()
            .find(|(a, f, _)| *a == a_r && *f == fwd)
            .map(|(_, _, l)| *l)
    }
}

/// The equilibrium on the holding stop for a robot segment `seg` of acceleration `a_r`
/// (Newton from the stroke `s`) and the oscillator's coefficients there, the rest of the state
/// as in `y` (same regime).
fn linearise(
    model: &Model,
    t: f64,
    y: &[f64],
    seg: &Segment,
    a_r: f64,
    s: f64,
) -> Option<Linearisation> {
    let m = model.p.m_t;
    let h = |s: f64| model.tool_force(t, y, seg, s, 0.0) - m * a_r;
    // equilibrium: Newton from the current stroke, kept on the stop
    let mut s_eq = if model.holding_depth(s) > 0.0 {
        s
    } else {
        s - model.holding_depth(s) * 1.01 - 1e-9
    };
    let mut converged = false;
    for _ in 0..40 {
        let depth = model.holding_depth(s_eq);
        if !(depth > 0.0) {
            return None;
        }
        let ds = 1e-6 * depth;
        let slope = (h(s_eq + ds) - h(s_eq - ds)) / (2.0 * ds);
        if !(slope > 0.0) {
            return None;
        }
        let mut step = -h(s_eq) / slope;
        while model.holding_depth(s_eq + step) <= 0.0 {
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
    let depth = model.holding_depth(s_eq);
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
    let g = |sd: f64| model.tool_force(t, y, seg, s_eq, sd);
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

#[cfg(test)]
mod tests {
    use super::Linearisations;
    use crate::config::Scene;
    use crate::model::Model;

    /// The tool resting on its forward stop at the preload, with the robot cruising: the
    /// equilibrium on the stop is found for a paper-like stop and for a steel one, whose depth
    /// (5e-8 m at 1e11 N/m^1.5) only a few ulp of the flange's position resolve.
    #[test]
    fn the_equilibrium_on_a_steel_stop_is_found() {
        for stiffness in ["6e5", "1e11", "1e12"] {
            let mut scene = Scene::default();
            scene.set_from_str("stops.stiffness", stiffness).unwrap();
            let m = Model::new(&scene);
            let mut lins = Linearisations::default();
            let y = m.y0.clone();
            let t = 0.05;
            let seg = *m.robot.current();
            let (x_r, _, a_r) = seg.at(t);
            // the tool where the preload left it, relative to the flange
            let i = m.layout.tool.unwrap();
            let s0 = -y[i];
            let mut z = y.clone();
            z[i] = x_r - s0;
            let l = lins.linearisation(&m, t, &z, &seg, a_r, s0);
            assert!(l.is_some(), "stops.stiffness = {stiffness}: no equilibrium");
        }
    }
}
