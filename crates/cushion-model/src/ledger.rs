//! The energy ledger (`docs/model.md`, section "Energy ledger"): the robot's work against what the
//! tool and object hold and what was dissipated, at the end of a run. Its residual is a free
//! accuracy check.

use crate::config::Module;
use crate::model::Model;
use crate::physics;

/// The terms of the energy ledger at the end of a run (`docs/model.md`, "Energy ledger"), J.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyLedger {
    /// Work done by the robot on the module, `int -F_r v_r dt`.
    pub work: f64,
    /// Change of the kinetic energy of tool and object.
    pub kinetic: f64,
    /// Change of the gas energy.
    pub gas: f64,
    /// Change of the elastic energy of contacts, stops and the bistable springs.
    pub elastic: f64,
    /// Dissipated: orifice, tool friction, contact damping, plane friction.
    pub dissipated: f64,
    /// `|work - (kinetic + gas + elastic + dissipated)|` over the largest term of the balance
    /// `W + E(0) = E(t) + D`: the work, the dissipation, each energy change, and the kinetic,
    /// gas and elastic energies held at the start and at the end.
    pub residual: f64,
}

/// Energy ledger of a finished run: `(residual, [W, dKE, dE_gas, dE_elastic, D_total])`.
pub(crate) fn energy_ledger(model: &Model, t: f64, y: &[f64]) -> Option<(f64, [f64; 5])> {
    balance(model, t, y).map(|(residual, _, terms)| (residual, terms))
}

/// The ledger's scale at `(t, y)`: its largest term (J), which the residual is relative to.
pub(crate) fn scale(model: &Model, t: f64, y: &[f64]) -> Option<f64> {
    balance(model, t, y).map(|(_, scale, _)| scale)
}

/// `(residual, scale, terms)` of the ledger at `(t, y)`.
fn balance(model: &Model, t: f64, y: &[f64]) -> Option<(f64, f64, [f64; 5])> {
    let l = model.layout;
    let w = y[l.work?];
    let p = &model.p;
    let seg0 = *model.robot.segment_at(0.0);
    let seg1 = *model.robot.segment_at(t);
    let tool_v = |t: f64, y: &[f64], seg: &physics::Segment| match l.tool {
        Some(i) => y[i + 1],
        None => seg.at(t).1,
    };
    let tool_x = |t: f64, y: &[f64], seg: &physics::Segment| match l.tool {
        Some(i) => y[i],
        None => seg.at(t).0,
    };
    let y0 = &model.y0;
    let ke = |t: f64, y: &[f64], seg: &physics::Segment| {
        let vt = tool_v(t, y, seg);
        let mut k = 0.5 * p.m_t * vt * vt;
        if let Some(j) = l.object {
            k += 0.5 * p.m_p * y[j + 1] * y[j + 1];
        }
        k
    };
    let stored = |t: f64, y: &[f64], seg: &physics::Segment| -> (f64, f64) {
        let (x_r, _, _) = seg.at(t);
        let x_t = tool_x(t, y, seg);
        let s = x_r - x_t;
        let mut gas = 0.0;
        let mut el = 0.0;
        match p.module {
            Module::Hydraulic => {
                gas = match l.liquid {
                    Some(q) => physics::gas_energy(p.p10, p.v_g0, 1.0, p.kappa, y[q + 1]),
                    None => physics::gas_energy(p.p10, p.v_g0, p.a_p, p.kappa, s),
                };
                if let Some(k) = l.e_liquid {
                    el += y[k];
                }
            }
            Module::Bistable => el += physics::bistable_energy(p.k_b, p.w, p.h, s + p.e),
            Module::Rigid => {}
        }
        if l.tool.is_some() {
            el += physics::hunt_crossley_energy(p.k_e, -s)
                + physics::hunt_crossley_energy(p.k_e, s - p.stroke);
        }
        if let Some(j) = l.object {
            el += physics::hunt_crossley_energy(p.k_c, x_t - y[j]);
        }
        (gas, el)
    };
    let (ke1, ke0) = (ke(t, y, &seg1), ke(0.0, y0, &seg0));
    let d_ke = ke1 - ke0;
    let (g1, e1) = stored(t, y, &seg1);
    let (g0, e0) = stored(0.0, y0, &seg0);
    let (d_gas, d_el) = (g1 - g0, e1 - e0);
    let d_total = l.dissipated.map_or(0.0, |k| y[k]);
    // The largest term of the balance `W + E(0) = E(t) + D` (`E` = kinetic + gas + elastic),
    // the energies held at either end included: in a scene where nothing happens (no impact,
    // the tool riding along at rest) the work and the changes are all of rounding size, and
    // their mismatch over the largest of them alone would be noise over noise (~1).
    let scale = [w, d_ke, d_gas, d_el, d_total, ke0, ke1, g0, g1, e0, e1]
        .into_iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let mismatch = w - (d_ke + d_gas + d_el + d_total);
    let residual = if scale > 0.0 {
        mismatch.abs() / scale
    } else {
        mismatch.abs()
    };
    Some((residual, scale, [w, d_ke, d_gas, d_el, d_total]))
}
