//! The energy ledger over a ringing tail (the other tails change nothing the ledger
//! integrates): the robot's work, exact for the tail's motion, and what the model's own force
//! law dissipates along it, by Gauss–Legendre quadrature, each added to its ledger state. The
//! residual then checks the closed form against the force law as it checks the integration,
//! instead of closing by construction.

use super::ringing_tail::RingingTail;
use super::tail::{Tail, TailKind};
use crate::model::{Model, MAX_STATES};

/// After an early end with a ringing tail (the other tails change nothing the ledger
/// integrates): the robot's work during it (exact for the tail's motion) and what the model's
/// force law dissipates along it ([`dissipation`]), each added to its ledger state, so that
/// the residual checks the closed form as it checks the integration. Once what the ringing
/// still has to lose is below rtol of the ledger's work over [`DISSIPATION_MISMATCH`], the
/// quadrature stops and that rest is added as the ringing loses it.
pub(crate) fn add_to_ledger(
    model: &Model,
    tail: &Tail,
    y_te: &[f64],
    t_end: f64,
    rtol: f64,
    y: &mut [f64],
) {
    let l = model.layout;
    let (TailKind::Ringing(ringing), Some(k_work)) = (&tail.kind, l.work) else {
        return;
    };
    y[k_work] += robot_work(ringing, model, t_end);
    let negligible = rtol * y_te[k_work].abs() / DISSIPATION_MISMATCH;
    if let Some(k) = l.dissipated {
        y[k] += dissipation(ringing, model, y_te, t_end, negligible);
    }
}

/// How far, relatively, the energy the closed form loses may depart from what the force law
/// dissipates along it, on the late, small-amplitude part of a ringing tail: over a whole tail
/// the two agree to 1.5 % (`tests::the_ledger_over_a_ringing_tail_checks_the_closed_form`),
/// but its last, smallest part, shared as in the last half period, departs by up to about 20 %
/// (on paper-hydraulic-dt10 with RK4 at 2e-5 s, a rest of up to ten times rtol of the work
/// moved the residual by 2.0 rtol of the work). Once what the ringing still has to
/// lose is below rtol of the work over this, it is added as the closed form loses it instead of
/// by quadrature: what that hides of the closed form's departure is about rtol of the work,
/// the size of the integrated ledger's own error at that rtol (on 72 scene variants the
/// residual moved by at most 1.0e-6 at rtol 1e-6; `tests::the_quadrature_stops_where_the_rest_is_negligible`). On the paper's hydraulic scenes it halves the quadrature's cost (from 8 % of
/// a run's instructions to 4.5 %).
const DISSIPATION_MISMATCH: f64 = 0.2;

/// Gauss–Legendre nodes on `[-1, 1]` (the positive half; each with its mirror) and weights:
/// six nodes a half period integrate the powers to about 2 % of the tail's dissipation (16
/// nodes a quarter period as the reference), a small share of a residual the closed form's own
/// error dominates.
const GAUSS_LEGENDRE: [(f64, f64); 3] = [
    (0.238_619_186_083_197, 0.467_913_934_572_691),
    (0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (0.932_469_514_203_152, 0.171_324_492_379_170_4),
];

/// The robot's work on the module during a ringing tail, J (the other tails have the robot
/// at rest or the tool riding with it: zero): per segment of constant `a_r`,
/// `int G v_r dt` with `G = m (a_r - s'')` is `m a_r dx_r - m [sd v_r] + m a_r ds`.
fn robot_work(tail: &RingingTail, m: &Model, t_end: f64) -> f64 {
    let m_t = m.p.m_t;
    let mut w = 0.0;
    for (k, pc) in tail.pieces.iter().enumerate() {
        let t1 = tail.pieces.get(k + 1).map_or(t_end, |n| n.t0);
        let seg = *m.robot.segment_at(pc.t0);
        let (x0, v0, _) = seg.at(pc.t0);
        let (x1, v1, _) = seg.at(t1);
        let (u0, sd0) = pc.ring.state(pc.t0);
        let (u1, sd1) = pc.ring.state(t1);
        w += m_t * pc.a_r * (x1 - x0) - m_t * (sd1 * v1 - sd0 * v0) + m_t * pc.a_r * (u1 - u0);
    }
    w
}

/// What the model's own force law dissipates along a ringing tail's motion to `t_end` (J): in
/// the orifice, the tool's friction and the stops' damping. The
/// powers are integrated by 6-point Gauss–Legendre on each half period of each piece of the
/// ringing (no contact opens or closes there; the orifice's `|sd|^3` has a kink where the
/// tool turns, which `GAUSS_LEGENDRE`'s accuracy allows for), until what the ringing's
/// energy `m (w0 a)^2 / 2` still has to lose in the piece has fallen below `negligible`
/// (J); that rest is added as it is lost. Closing the ledger with this (and the robot's
/// work) leaves a residual that measures how far the closed form departs from the force law
/// (`tests::the_ledger_over_a_ringing_tail_checks_the_closed_form`,
/// `tests/model/early_end.rs::the_ledger_over_a_ringing_tail_shrinks_with_the_tolerance`).
fn dissipation(tail: &RingingTail, m: &Model, y_te: &[f64], t_end: f64, negligible: f64) -> f64 {
    let n = m.layout.n.clamp(1, MAX_STATES);
    let (Some(i), mut z) = (m.layout.tool, [0.0; MAX_STATES]) else {
        return 0.0;
    };
    z[..n].copy_from_slice(&y_te[..n]);
    let mut d = 0.0;
    for (k, pc) in tail.pieces.iter().enumerate() {
        let t1 = tail.pieces.get(k + 1).map_or(t_end, |n| n.t0);
        let seg = *m.robot.segment_at(pc.t0);
        let half = std::f64::consts::PI / pc.ring.w0;
        let energy = |t: f64| pc.ring.energy(m.p.m_t, pc.ring.amplitude(t));
        let energy_end = energy(t1);
        let mut ta = pc.t0;
        while ta < t1 {
            let tb = (ta + half).min(t1);
            let (mid, rad) = (0.5 * (ta + tb), 0.5 * (tb - ta));
            let mut dw = 0.0;
            for (x, w) in GAUSS_LEGENDRE {
                for t in [mid - rad * x, mid + rad * x] {
                    // the tool as the ringing has it (the object, out of reach, does not
                    // enter the powers)
                    let (u, sd) = pc.ring.state(t);
                    let (x_r, v_r, _) = seg.at(t);
                    z[i] = x_r - (pc.s_eq + u);
                    z[i + 1] = v_r - sd;
                    let e = m.eval(t, &z[..n], &seg, &m.regime);
                    dw += w * rad * (e.p_orifice + e.p_friction + e.p_contact);
                }
            }
            d += dw;
            ta = tb;
            let left = energy(ta) - energy_end;
            if ta < t1 && left < negligible {
                // the rest, below `negligible`: the energy the ringing still loses
                if dw > 0.0 {
                    d += left;
                }
                break;
            }
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::{dissipation, robot_work};
    use crate::config::Scene;
    use crate::early_end::linearisation::Linearisations;
    use crate::early_end::ringing::{Coefficients, Ringing};
    use crate::early_end::ringing_tail::{Piece, RingingTail};
    use crate::early_end::tail::{Tail, TailKind};
    use crate::ledger::energy_ledger;
    use crate::model::Model;

    /// The ringing of a ringing tail.
    fn ringing_of(tail: &Tail) -> &RingingTail {
        match &tail.kind {
            TailKind::Ringing(r) => r,
            _ => unreachable!("a ringing tail"),
        }
    }

    /// The paper's hydraulic tool ringing on its forward stop under a standing robot, from 0.2
    /// of the stop's depth, over 20 periods: what the force law dissipates along the closed
    /// form against the energy the tool and module lose, `(dissipated, lost)` in J. The closed
    /// form's linear damping is scaled by `damping_scale`.
    fn ringing_balance(damping_scale: f64) -> (f64, f64) {
        let (m, tail, y, t_end) = ringing(damping_scale);
        assert_eq!(robot_work(ringing_of(&tail), &m, tail.t), 0.0);
        let dissipated: f64 = dissipation(ringing_of(&tail), &m, &y, t_end, 0.0);
        let stored = |t: f64, y: &[f64]| {
            let v = energy_ledger(&m, t, y).unwrap().1;
            v[1] + v[2] + v[3]
        };
        let y_end = tail.state_at(&m, &y, t_end);
        (dissipated, stored(tail.t, &y) - stored(t_end, &y_end))
    }

    /// That ringing: the model, its tail, the state at the tail's start and the end time.
    fn ringing(damping_scale: f64) -> (Model, Tail, Vec<f64>, f64) {
        let mut scene = Scene::default();
        scene.set_from_str("object.enabled", "false").unwrap();
        let mut m = Model::new(&scene);
        let t = m.robot.brake(0.0);
        m.robot.on_time(t);
        let seg = *m.robot.current();
        let i = m.layout.tool.unwrap();
        let mut y = m.y0.clone();
        let lin = Linearisations::default()
            .linearisation(&m, t, &y, &seg, 0.0, m.preload_stroke)
            .unwrap();
        let u0 = 0.2 * lin.depth;
        y[i] = seg.at(t).0 - (lin.s_eq + u0);
        y[i + 1] = 0.0;
        let coef = Coefficients {
            c: lin.coef.c * damping_scale,
            ..lin.coef
        };
        let ring = Ringing::through(&coef, t, u0, 0.0).unwrap();
        let t_end = t + 20.0 * 2.0 * std::f64::consts::PI / ring.w0;
        let piece = Piece {
            t0: t,
            s_eq: lin.s_eq,
            depth: lin.depth,
            a_r: 0.0,
            ring,
        };
        let tail = Tail {
            t,
            kind: TailKind::Ringing(RingingTail {
                pieces: vec![piece],
                brake: None,
                stop: None,
                resume: None,
            }),
        };
        assert_eq!(robot_work(ringing_of(&tail), &m, t_end), 0.0);
        (m, tail, y, t_end)
    }

    /// Stopping the quadrature once the rest is below rtol of the scale over
    /// `DISSIPATION_MISMATCH`, and adding that rest as the closed form loses it, changes the
    /// dissipation by less than rtol of the scale (here the energy the ringing loses, which
    /// falls by 17 e-folds over the 20 periods), against the quadrature to the end.
    #[test]
    fn the_quadrature_stops_where_the_rest_is_negligible() {
        let (m, tail, y, t_end) = ringing(1.0);
        let full: f64 = dissipation(ringing_of(&tail), &m, &y, t_end, 0.0);
        for rtol in [1e-4, 1e-6, 1e-8] {
            let negligible = rtol * full / super::DISSIPATION_MISMATCH;
            let d: f64 = dissipation(ringing_of(&tail), &m, &y, t_end, negligible);
            assert!(d != full, "rtol {rtol}: the quadrature ran to the end");
            assert!(
                (d - full).abs() <= rtol * full,
                "rtol {rtol}: {d:e} J against {full:e} J"
            );
        }
    }

    /// Along the closed form, the force law dissipates what the ringing loses, to 1.5 % (0.75 %
    /// measured: the closed form's error at 0.2 of the depth); a closed form whose damping is
    /// 30 % too strong is caught by the same balance (off by 21 %, more than the 10 % asked).
    /// So the ledger over a ringing tail checks the closed form instead of closing by
    /// construction.
    #[test]
    fn the_ledger_over_a_ringing_tail_checks_the_closed_form() {
        let (d, lost) = ringing_balance(1.0);
        assert!(
            d > 0.0 && (d - lost).abs() <= 0.015 * lost,
            "{d:e} J against {lost:e} J"
        );
        let (d, lost) = ringing_balance(1.3);
        assert!((d - lost).abs() > 0.1 * lost, "{d:e} J against {lost:e} J");
    }
}
