//! The model's Jacobian `df/dy` and `df/dt`, exact, for the implicit method: the same physics
//! as `forces.rs`, part by part, each quantity carried with its gradient (forward-mode
//! differentiation by hand: [`D`] is a value and its derivatives in the six dynamic states and
//! time). The ledger's quadratures and the contact impulse feed back into nothing, so their
//! columns are zero; their rows are the derivatives of their power terms, which the
//! Rosenbrock method needs for its order on those components too.
//!
//! Within a regime the right-hand side is smooth (every kink is an event), so the derivative
//! is that of the regime's branch. Guarded by
//! `tests::the_jacobian_matches_finite_differences_in_every_regime`.

use super::{Model, Regime};
use crate::config::Module;
use crate::physics;
use cushion_ode::{Matrix, State};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The variables a gradient runs over: tool, liquid and object states, and time.
const XT: usize = 0;
const VT: usize = 1;
const PM: usize = 2;
const VX: usize = 3;
const XP: usize = 4;
const VP: usize = 5;
const T: usize = 6;
const VARS: usize = 7;

/// A value with its gradient in `x_t, v_t, p_m, V_x, x_p, v_p, t`.
#[derive(Clone, Copy, Debug, Default)]
struct D {
    v: f64,
    g: [f64; VARS],
}

impl D {
    fn constant(v: f64) -> D {
        D { v, g: [0.0; VARS] }
    }

    /// The variable `i` at value `v`.
    fn var(v: f64, i: usize) -> D {
        let mut g = [0.0; VARS];
        g[i] = 1.0;
        D { v, g }
    }

    /// `f(self)` with `f' = slope` at `self.v`.
    fn chain(self, v: f64, slope: f64) -> D {
        D {
            v,
            g: self.g.map(|x| x * slope),
        }
    }

    /// `d^1.5` for `d > 0`, else 0.
    fn pos15(self) -> D {
        if self.v > 0.0 {
            let r = self.v.sqrt();
            self.chain(self.v * r, 1.5 * r)
        } else {
            D::constant(0.0)
        }
    }
}

impl Add for D {
    type Output = D;
    fn add(self, o: D) -> D {
        D {
            v: self.v + o.v,
            g: std::array::from_fn(|i| self.g[i] + o.g[i]),
        }
    }
}

impl Sub for D {
    type Output = D;
    fn sub(self, o: D) -> D {
        self + (-o)
    }
}

impl Neg for D {
    type Output = D;
    fn neg(self) -> D {
        self * -1.0
    }
}

// The product and quotient rules: clippy's suspicion of `+` in `Mul` does not apply.
#[allow(clippy::suspicious_arithmetic_impl)]
impl Mul for D {
    type Output = D;
    fn mul(self, o: D) -> D {
        D {
            v: self.v * o.v,
            g: std::array::from_fn(|i| self.g[i] * o.v + self.v * o.g[i]),
        }
    }
}

impl Mul<f64> for D {
    type Output = D;
    fn mul(self, k: f64) -> D {
        D {
            v: self.v * k,
            g: self.g.map(|x| x * k),
        }
    }
}

#[allow(clippy::suspicious_arithmetic_impl)]
impl Div for D {
    type Output = D;
    fn div(self, o: D) -> D {
        let q = self.v / o.v;
        D {
            v: q,
            g: std::array::from_fn(|i| (self.g[i] - q * o.g[i]) / o.v),
        }
    }
}

impl Div<f64> for D {
    type Output = D;
    fn div(self, k: f64) -> D {
        self * (1.0 / k)
    }
}

/// Hunt–Crossley force `d^1.5 (k + chi dd)` (0 once released), as in `forces.rs`.
fn contact_force(k: f64, chi: f64, d: D, dd: D, released: bool) -> D {
    if released {
        D::constant(0.0)
    } else {
        d.pos15() * (dd * chi + D::constant(k))
    }
}

/// The right-hand side's terms with their gradients.
struct Terms {
    v_t: D,
    a_t: D,
    v_p: D,
    a_p: D,
    p_work: D,
    p_orifice: D,
    p_friction: D,
    p_contact: D,
    p_plane: D,
    f_c: D,
    dp_m: D,
    flow: D,
    p_liquid: D,
}

/// The tool's kinematics and the forces on it, with their gradients: position, speed, the
/// stroke rate `sd`, and the module's and the stops' forces (+ forward).
struct ToolForces {
    x_t: D,
    v_t: D,
    sd: D,
    f_module: D,
    f_stop: D,
}

impl Model {
    /// `df/dy` and `df/dt` at `(t, y)` in regime `r`.
    pub(crate) fn jacobians<const N: usize>(
        &self,
        t: f64,
        y: &State<N>,
        r: &Regime,
    ) -> (Matrix<N>, State<N>) {
        let e = self.terms(t, y.as_slice(), r);
        let l = &self.layout;
        // the state index of each variable of a gradient
        let mut column = [None; VARS - 1];
        if let Some(i) = l.tool {
            column[XT] = Some(i);
            column[VT] = Some(i + 1);
        }
        if let Some(q) = l.liquid {
            column[PM] = Some(q);
            column[VX] = Some(q + 1);
        }
        if let Some(j) = l.object {
            column[XP] = Some(j);
            column[VP] = Some(j + 1);
        }
        let mut jac = Matrix::<N>::zeros();
        let mut dfdt = State::<N>::zeros();
        let mut row = |k: usize, d: &D| {
            for (var, c) in column.iter().enumerate() {
                if let Some(c) = c {
                    jac[(k, *c)] = d.g[var];
                }
            }
            dfdt[k] = d.g[T];
        };
        if let Some(i) = l.tool {
            row(i, &e.v_t);
            row(i + 1, &e.a_t);
        }
        if let Some(j) = l.object {
            let v_p = if r.obj_stuck { D::constant(0.0) } else { e.v_p };
            row(j, &v_p);
            row(j + 1, &e.a_p);
        }
        let dissipated = e.p_orifice + e.p_friction + e.p_contact + e.p_plane;
        let rows = [
            (l.work, &e.p_work),
            (l.dissipated, &dissipated),
            (l.contact_impulse, &e.f_c),
            (l.e_liquid, &e.p_liquid),
        ];
        for (k, d) in rows {
            if let Some(k) = k {
                row(k, d);
            }
        }
        if let Some(q) = l.liquid {
            row(q, &e.dp_m);
            row(q + 1, &e.flow);
        }
        (jac, dfdt)
    }

    /// `forces.rs`'s `eval_inline`, each term with its gradient.
    fn terms(&self, t: f64, y: &[f64], r: &Regime) -> Terms {
        let (xr, vr, ar) = self.robot_at(t);
        let zero = D::constant(0.0);
        let mut e = Terms {
            v_t: vr,
            a_t: ar,
            v_p: zero,
            a_p: zero,
            p_work: zero,
            p_orifice: zero,
            p_friction: zero,
            p_contact: zero,
            p_plane: zero,
            f_c: zero,
            dp_m: zero,
            flow: zero,
            p_liquid: zero,
        };
        let tool = self.tool_forces(y, r, xr, vr, &mut e);
        e.v_t = tool.v_t;
        self.object_contact(y, r, &tool, &mut e);
        self.tool_balance(r, vr, ar, &tool, &mut e);
        self.object_acceleration(r, &mut e);
        e
    }

    /// The flange's position, speed and acceleration at `t`, each with its derivative in
    /// time (the robot is prescribed: it depends on no state).
    fn robot_at(&self, t: f64) -> (D, D, D) {
        let (x_r, v_r, a_r) = self.robot.current().at(t);
        let mut xr = D::constant(x_r);
        xr.g[T] = v_r;
        let mut vr = D::constant(v_r);
        vr.g[T] = a_r;
        (xr, vr, D::constant(a_r))
    }

    /// The tool's kinematics and the forces of its stops and its module (the flange and no
    /// force for the rigid module, whose tool is the flange); the stops' damping adds to
    /// `e.p_contact`, the module's terms to `e`.
    fn tool_forces(&self, y: &[f64], r: &Regime, xr: D, vr: D, e: &mut Terms) -> ToolForces {
        let zero = D::constant(0.0);
        let Some(i) = self.layout.tool else {
            return ToolForces {
                x_t: xr,
                v_t: vr,
                sd: zero,
                f_module: zero,
                f_stop: zero,
            };
        };
        let x_t = D::var(y[i], XT);
        let v_t = D::var(y[i + 1], VT);
        let s = xr - x_t;
        let sd = vr - v_t;
        let f_stop = self.stop_force(r, s, sd, e);
        let f_module = match self.p.module {
            Module::Hydraulic if self.layout.liquid.is_some() => {
                self.compressible_hydraulic_force(y, s, sd, e)
            }
            Module::Hydraulic => self.incompressible_hydraulic_force(r, s, sd, e),
            Module::Bistable => self.bistable_spring_force(s),
            Module::Rigid => zero,
        };
        ToolForces {
            x_t,
            v_t,
            sd,
            f_module,
            f_stop,
        }
    }

    /// The end-stops' force on the tool at stroke `s` and rate `sd` (+ forward: the back stop
    /// pushes forward, the forward stop back); their damping's power adds to `e.p_contact`.
    fn stop_force(&self, r: &Regime, s: D, sd: D, e: &mut Terms) -> D {
        let p = &self.p;
        let zero = D::constant(0.0);
        let (mut f_fwd, mut f_back) = (zero, zero);
        if r.fwd {
            let (d, dd) = (-s, -sd);
            f_fwd = contact_force(p.k_e, p.chi_e, d, dd, r.stop_released);
            e.p_contact = e.p_contact + (f_fwd - d.pos15() * p.k_e) * dd;
        }
        if r.back {
            let d = s - D::constant(p.stroke);
            f_back = contact_force(p.k_e, p.chi_e, d, sd, r.stop_released);
            e.p_contact = e.p_contact + (f_back - d.pos15() * p.k_e) * sd;
        }
        f_back - f_fwd
    }

    /// The hydraulic module with a compressible liquid: the force of the main chamber's
    /// pressure `p_m` (a state) on the piston; the chamber's pressure rate, the flow the
    /// orifice passes (turbulent down to the transition pressure, laminar below), the
    /// orifice's loss and the power stored in the liquid go to `e`.
    fn compressible_hydraulic_force(&self, y: &[f64], s: D, sd: D, e: &mut Terms) -> D {
        let p = &self.p;
        let q = self.layout.liquid.unwrap_or(0);
        let p_m = D::var(y[q], PM);
        let v_x = D::var(y[q + 1], VX);
        let p1 = self.gas.exact(v_x.v);
        let p1 = v_x.chain(p1, self.gas.slope(v_x.v, p1));
        let dp = p_m - p1;
        let k = p.a_o * (2.0 / (p.c0 * p.rho)).sqrt();
        let m = dp.v * dp.v + p.p_transition * p.p_transition;
        let flow = dp.chain(
            physics::orifice_flow(p.a_o, p.c0, p.rho, p.p_transition, dp.v),
            k * (0.5 * dp.v * dp.v + p.p_transition * p.p_transition) / (m * m.sqrt().sqrt()),
        );
        let displaced = sd * p.a_p - flow;
        let v_m = D::constant(p.v_m0) - s * p.a_p;
        e.dp_m = displaced * p.beta / v_m;
        e.flow = flow;
        e.p_orifice = dp * flow;
        e.p_liquid = p_m * displaced;
        p_m * p.a_p
    }

    /// The hydraulic module with an incompressible liquid: the gas pressure and the orifice's
    /// pressure drop on the piston (while cavitating, the chamber holds `p_cav`); the
    /// orifice's loss goes to `e`.
    fn incompressible_hydraulic_force(&self, r: &Regime, s: D, sd: D, e: &mut Terms) -> D {
        let p = &self.p;
        let p1 = self.gas.exact(s.v);
        let p1 = s.chain(p1, self.gas.slope(s.v, p1));
        let ratio = p.a_p / p.a_o;
        let c = 0.5 * p.c0 * p.rho * ratio * ratio;
        let mut dp = sd.chain(c * sd.v * sd.v.abs(), 2.0 * c * sd.v.abs());
        if r.cavitating {
            dp = D::constant(p.p_cav.unwrap_or(0.0)) - p1;
        }
        e.p_orifice = dp * sd * p.a_p;
        (p1 + dp) * p.a_p
    }

    /// The bistable module: the von Mises springs' force at stroke `s`.
    fn bistable_spring_force(&self, s: D) -> D {
        let p = &self.p;
        let x = s + D::constant(p.e);
        let (w2, l0) = (p.w * p.w, (p.w * p.w + p.h * p.h).sqrt());
        let u = p.h - x.v;
        let l = (w2 + u * u).sqrt();
        // dF/dx = -2 k_b (L0 w^2 / l^3 - 1)
        let slope = -2.0 * p.k_b * (l0 * w2 / (l * l * l) - 1.0);
        x.chain(physics::bistable_force(p.k_b, p.w, p.h, x.v), slope)
    }

    /// The object's speed and, in contact, the tool's force on it; the contact's damping
    /// adds to `e.p_contact`.
    fn object_contact(&self, y: &[f64], r: &Regime, tool: &ToolForces, e: &mut Terms) {
        let p = &self.p;
        if let Some(j) = self.layout.object {
            let x_p = D::var(y[j], XP);
            let v_p = D::var(y[j + 1], VP);
            e.v_p = v_p;
            if r.obj_contact {
                let (d, dd) = (tool.x_t - x_p, tool.v_t - v_p);
                e.f_c = contact_force(p.k_c, p.chi_c, d, dd, r.obj_released);
                e.p_contact = e.p_contact + (e.f_c - d.pos15() * p.k_c) * dd;
            }
        }
    }

    /// The balance of forces on the tool: its acceleration (the flange's while it moves with
    /// the robot, the friction then being what holds it), its friction's loss, and the robot's
    /// power `G v_r`.
    fn tool_balance(&self, r: &Regime, vr: D, ar: D, tool: &ToolForces, e: &mut Terms) {
        let p = &self.p;
        let g;
        if p.module == Module::Rigid || r.tool_stuck {
            e.a_t = ar;
            g = ar * p.m_t + e.f_c;
            if p.module != Module::Rigid {
                let f_f = g - tool.f_module - tool.f_stop;
                e.p_friction = f_f * tool.sd;
            }
        } else {
            let f_f = tool.sd * p.b + D::constant(p.d * r.tool_dir);
            g = tool.f_module + f_f + tool.f_stop;
            e.a_t = (g - e.f_c) / p.m_t;
            e.p_friction = f_f * tool.sd;
        }
        e.p_work = g * vr;
    }

    /// The object's acceleration under the contact force and the plane's friction (none while
    /// stuck), and the friction's loss.
    fn object_acceleration(&self, r: &Regime, e: &mut Terms) {
        let p = &self.p;
        if self.layout.object.is_some() {
            if p.mu_n > 0.0 {
                if r.obj_stuck {
                    e.a_p = D::constant(0.0);
                } else {
                    e.a_p = (e.f_c - D::constant(p.mu_n)) / p.m_p;
                    e.p_plane = e.v_p * p.mu_n;
                }
            } else {
                e.a_p = e.f_c / p.m_p;
            }
        }
    }
}

#[cfg(test)]
mod tests;
