//! The force laws of `docs/model.md` (sections "Contacts", "Hydraulic module", "Bistable module"),
//! as plain functions of their arguments, and the potential energies that go with them (for the
//! energy ledger).
//!
//! Sign conventions (`docs/model.md`, section "Scene and frames"): +x is the direction of approach;
//! stroke `s = x_r - x_t`, `sd = v_r - v_t`. A module force `G` is the force the module exerts on
//! the tool along +x; it exerts `-G` on the flange, so the force on the robot is `F_r = -G`.
//!
//! Notes where the model goes beyond the paper's equations:
//! - Hunt–Crossley `F = k d^1.5 + chi d^1.5 dd` is clamped at `F >= 0`: the unclamped law pulls
//!   the bodies together during restitution when `dd < -k/chi` (for the paper's contact values,
//!   separation faster than 0.44 m/s), which a contact between bodies that are not glued cannot do.
//!   The energy ledger books the clamped part as contact dissipation: with `E_el = k d^2.5 / 2.5`,
//!   the dissipated power is `(F - k d^1.5) dd`, which is `>= 0` on both branches.
//! - The orifice law of the paper (eq. 1) squares the relative speed and loses the flow's
//!   direction; here `dp = 0.5 c0 rho (A_p/A_o)^2 sd |sd|` opposes the flow both ways.

/// Hunt–Crossley contact force for penetration `d` (m) and penetration rate `dd` (m/s), with
/// stiffness `k` (N/m^1.5) and damping `chi` (N s/m^2.5): `max(0, d^1.5 (k + chi dd))` for
/// `d > 0`, else 0. Returns N (>= 0, pushing the bodies apart).
#[inline]
pub fn hunt_crossley(k: f64, chi: f64, d: f64, dd: f64) -> f64 {
    if d <= 0.0 {
        return 0.0;
    }
    let d15 = d * d.sqrt();
    (d15 * (k + chi * dd)).max(0.0)
}

/// Elastic energy stored in a Hunt–Crossley contact: `k d^2.5 / 2.5` for `d > 0`, J.
#[inline]
pub fn hunt_crossley_energy(k: f64, d: f64) -> f64 {
    if d <= 0.0 {
        0.0
    } else {
        k * d * d * d.sqrt() / 2.5
    }
}

/// Orifice pressure drop (Pa) for relative speed `sd = v_r - v_t` (m/s): positive when the tool
/// is pushed back (`sd > 0`, liquid flows into the auxiliary cylinder).
#[inline]
pub fn orifice_pressure_drop(c0: f64, rho: f64, a_p: f64, a_o: f64, sd: f64) -> f64 {
    let r = a_p / a_o;
    0.5 * c0 * rho * r * r * sd * sd.abs()
}

/// The pressure difference across an orifice (Pa) at which its flow turns from laminar to
/// turbulent: where the turbulent law's jet speed `sqrt(2 dp / (c0 rho))` reaches the critical
/// Reynolds number's, `Re_cr nu / D` with `D = 2 R_o`.
pub fn orifice_transition_pressure(c0: f64, rho: f64, nu: f64, re_cr: f64, r_o: f64) -> f64 {
    let v = re_cr * nu / (2.0 * r_o);
    0.5 * c0 * rho * v * v
}

/// Flow through an orifice (m^3/s) for a pressure difference `dp` (Pa), turbulent above the
/// transition pressure `p_tr` and laminar below it, in one smooth law (Simscape Fluids' local
/// restriction; Merritt, Hydraulic Control Systems, sec. 2.9):
/// `Q = A_o sqrt(2 / (c0 rho)) dp / (dp^2 + p_tr^2)^(1/4)`. For `|dp| >> p_tr` it is the
/// turbulent law `A_o sgn(dp) sqrt(2 |dp| / (c0 rho))`, the lumped model's solved for the flow;
/// for `|dp| << p_tr` the flow is proportional to `dp`, so its derivative at rest is finite
/// (the turbulent law's is infinite, which made the compressible model infinitely stiff at
/// rest).
#[inline]
pub fn orifice_flow(a_o: f64, c0: f64, rho: f64, p_tr: f64, dp: f64) -> f64 {
    a_o * (2.0 / (c0 * rho)).sqrt() * dp / (dp * dp + p_tr * p_tr).sqrt().sqrt()
}

/// Adiabatic gas pressure (Pa) at stroke `s`: `p10 (V_g0 / (V_g0 - A_p s))^kappa`.
#[inline]
pub fn gas_pressure(p10: f64, v_g0: f64, a_p: f64, kappa: f64, s: f64) -> f64 {
    // exp(kappa ln x) rather than powf: the same to a few ulp here, and several times cheaper
    // than glibc's correctly rounded pow. The right-hand side uses it only now and then
    // (`gas_law.rs` evaluates the series about its last value in between).
    p10 * (kappa * (v_g0 / (v_g0 - a_p * s)).ln()).exp()
}

/// Energy stored in the gas relative to `s = 0` (J): `int_0^s p1 A_p ds`
/// `= p10 V_g0^kappa / (kappa - 1) (V^(1-kappa) - V_g0^(1-kappa))`, `V = V_g0 - A_p s`.
#[inline]
pub fn gas_energy(p10: f64, v_g0: f64, a_p: f64, kappa: f64, s: f64) -> f64 {
    let v = v_g0 - a_p * s;
    p10 * v_g0 / (kappa - 1.0) * ((v_g0 / v).powf(kappa - 1.0) - 1.0)
}

/// Von Mises (bistable) element force on the tool, N (+ = forward), at `x = s + e` (m):
/// `2 k_b (h - x) (L0 / sqrt(w^2 + (h - x)^2) - 1)`, `L0 = sqrt(w^2 + h^2)`.
#[inline]
pub fn bistable_force(k_b: f64, w: f64, h: f64, x: f64) -> f64 {
    let l0 = (w * w + h * h).sqrt();
    let y = h - x;
    2.0 * k_b * y * (l0 / (w * w + y * y).sqrt() - 1.0)
}

/// Energy stored in the two springs of the von Mises element at `x` (J): `k_b (l - L0)^2`,
/// with `l = sqrt(w^2 + (h - x)^2)`. Its derivative in `x` is [`bistable_force`].
#[inline]
pub fn bistable_energy(k_b: f64, w: f64, h: f64, x: f64) -> f64 {
    let l0 = (w * w + h * h).sqrt();
    let y = h - x;
    let l = (w * w + y * y).sqrt();
    k_b * (l - l0) * (l - l0)
}

/// Kinetic friction on the tool (N, + = forward): `d * dir + b * sd`, where `dir` is the sign of
/// `sd` during slip (set by the stick-slip events, never computed from a tiny `sd`).
#[inline]
pub fn tool_friction(d: f64, b: f64, sd: f64, dir: f64) -> f64 {
    d * dir + b * sd
}

/// Standard gravity for the plane friction, m/s^2.
pub const GRAVITY: f64 = 9.80665;

/// One segment of the robot's trapezoidal profile: constant acceleration from `t0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub t0: f64,
    pub x0: f64,
    pub v0: f64,
    pub a: f64,
    pub phase: Phase,
}

/// Phases of the robot profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Accelerating,
    Cruising,
    Braking,
    Stopped,
}

impl Segment {
    /// Position (m), speed (m/s), acceleration (m/s^2) at `t`.
    #[inline]
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let dt = t - self.t0;
        (
            self.x0 + dt * (self.v0 + 0.5 * self.a * dt),
            self.v0 + self.a * dt,
            self.a,
        )
    }

    /// The segment that follows this one from `t`: starting where this one is at `t`, with
    /// speed `v` (m/s) and acceleration `a` (m/s^2).
    pub fn then(&self, t: f64, v: f64, a: f64, phase: Phase) -> Segment {
        Segment {
            t0: t,
            x0: self.at(t).0,
            v0: v,
            a,
            phase,
        }
    }

    /// Braking from `t` at `a_brake` (m/s^2, positive), from this segment's speed there (never
    /// backwards).
    pub fn braking_from(&self, t: f64, a_brake: f64) -> Segment {
        self.then(t, self.at(t).1.max(0.0), -a_brake, Phase::Braking)
    }

    /// When a braking segment comes to rest (s).
    pub fn stop_time(&self) -> f64 {
        self.t0 + self.v0 / -self.a
    }

    /// Standing from `t` where this segment is then.
    pub fn stopped_at(&self, t: f64) -> Segment {
        self.then(t, 0.0, 0.0, Phase::Stopped)
    }
}

/// The robot's prescribed motion, built segment by segment as the run decides it (the brake
/// time is known only after detection). `x_r(0) = 0`.
#[derive(Clone, Debug)]
pub struct RobotProfile {
    segs: [Segment; 5],
    n: usize,
    pub v_max: f64,
    pub a_brake: f64,
    /// End of the acceleration from rest (a time stop), if the robot starts at rest.
    pub t_cruise: Option<f64>,
    pub t_brake: Option<f64>,
    pub t_stop: Option<f64>,
}

impl RobotProfile {
    /// Cruising at `v_max` from `t = 0`, or from rest accelerating at `a_acc`.
    pub fn new(v_max: f64, a_brake: f64, from_rest: Option<f64>) -> RobotProfile {
        let first = match from_rest {
            None => Segment {
                t0: 0.0,
                x0: 0.0,
                v0: v_max,
                a: 0.0,
                phase: Phase::Cruising,
            },
            Some(a) => Segment {
                t0: 0.0,
                x0: 0.0,
                v0: 0.0,
                a,
                phase: Phase::Accelerating,
            },
        };
        RobotProfile {
            segs: [first; 5],
            n: 1,
            v_max,
            a_brake,
            t_cruise: from_rest.map(|a| v_max / a),
            t_brake: None,
            t_stop: None,
        }
    }

    /// The current (latest) segment: the regime the right-hand side integrates in.
    #[inline]
    pub fn current(&self) -> &Segment {
        &self.segs[self.n - 1]
    }

    /// The segment that holds `t` (right-continuous at kinks).
    #[inline]
    pub fn segment_at(&self, t: f64) -> &Segment {
        let mut i = self.n - 1;
        while i > 0 && t < self.segs[i].t0 {
            i -= 1;
        }
        &self.segs[i]
    }

    fn push(&mut self, seg: Segment) {
        if self.n < self.segs.len() {
            self.segs[self.n] = seg;
            self.n += 1;
        }
    }

    /// Begin braking at `t`; returns the time the robot will stand still.
    pub fn brake(&mut self, t: f64) -> f64 {
        let braking = self.current().braking_from(t, self.a_brake);
        let t_stop = braking.stop_time();
        self.push(braking);
        self.t_brake = Some(t);
        self.t_stop = Some(t_stop);
        t_stop
    }

    /// Handle a time stop at `t`; returns the name of the kink it was, if any.
    pub fn on_time(&mut self, t: f64) -> Option<&'static str> {
        let near = |a: Option<f64>| a.is_some_and(|a| (t - a).abs() <= 1e-12 * (1.0 + a.abs()));
        if near(self.t_stop) && self.current().phase == Phase::Braking {
            self.push(self.current().stopped_at(t));
            return Some("robot_stopped");
        }
        if near(self.t_cruise) && self.current().phase == Phase::Accelerating {
            self.push(self.current().then(t, self.v_max, 0.0, Phase::Cruising));
            return Some("robot_cruising");
        }
        None
    }

    pub fn stopped(&self) -> bool {
        self.current().phase == Phase::Stopped
    }
}

/// Solve `f(x) = 0` on `[a, b]` with `f(a) < 0 < f(b)` (or the reverse) by the Illinois variant
/// of regula falsi, to the last bits of `x`. Returns the midpoint of the final bracket.
pub fn find_root(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let mut fa = f(a);
    let mut fb = f(b);
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let mut side = 0i32;
    for _ in 0..200 {
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !(c > a.min(b) && c < a.max(b)) {
            c = 0.5 * (a + b);
        }
        let fc = f(c);
        if fc == 0.0 {
            return c;
        }
        if (fc < 0.0) == (fa < 0.0) {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
        if (b - a).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
            break;
        }
    }
    0.5 * (a + b)
}

/// Static preload equilibrium on the forward stop: the `s0 <= 0` where the stop's elastic force
/// `k_e (-s0)^1.5` balances the module's preload `preload(s0)` (N, + = forward). A preload that
/// does not push forward at `s = 0` gives `s0 = 0`.
pub fn preload_equilibrium(k_e: f64, preload: impl Fn(f64) -> f64) -> f64 {
    let f0 = preload(0.0);
    if f0.is_nan() || f0 <= 0.0 {
        return 0.0;
    }
    // g(delta) = k_e delta^1.5 - preload(-delta): negative at 0, grows without bound.
    let g = |delta: f64| k_e * delta * delta.sqrt() - preload(-delta);
    let mut hi = (f0 / k_e).powf(2.0 / 3.0).max(1e-12);
    let mut n = 0;
    while g(hi) <= 0.0 && n < 200 {
        hi *= 2.0;
        n += 1;
    }
    -find_root(g, 0.0, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
    }

    #[test]
    fn hunt_crossley_by_hand() {
        // d = 1e-4 m: d^1.5 = 1e-6; k = 0.6e6 -> 0.6 N elastic; dd = 0.1 -> chi d^1.5 dd = 0.135 N.
        assert!(close(hunt_crossley(0.6e6, 1.35e6, 1e-4, 0.1), 0.735, 1e-12));
        assert!(close(
            hunt_crossley(0.6e6, 1.35e6, 1e-4, -0.1),
            0.6 - 0.135,
            1e-12
        ));
        // fast separation: unclamped law would pull (0.6 - 1.35 = -0.75 N); clamped to 0.
        assert_eq!(hunt_crossley(0.6e6, 1.35e6, 1e-4, -1.0), 0.0);
        // no penetration, no force
        assert_eq!(hunt_crossley(0.6e6, 1.35e6, -1e-4, 5.0), 0.0);
        assert_eq!(hunt_crossley(0.6e6, 1.35e6, 0.0, 5.0), 0.0);
        // energy: k d^2.5 / 2.5 = 0.6e6 * 1e-10 / 2.5
        assert!(close(hunt_crossley_energy(0.6e6, 1e-4), 2.4e-5, 1e-12));
    }

    #[test]
    fn orifice_flow_is_turbulent_above_the_transition_and_laminar_below() {
        let (a_o, c0, rho) = (std::f64::consts::PI * 0.008f64.powi(2), 3.0, 900.0);
        // Re_cr 12, nu 3.2e-5 m^2/s, D 16 mm: v_cr = 0.024 m/s, p_tr = 0.5 c0 rho v_cr^2
        let p_tr = orifice_transition_pressure(c0, rho, 3.2e-5, 12.0, 0.008);
        assert!((p_tr - 0.5 * 3.0 * 900.0 * 0.024f64.powi(2)).abs() < 1e-12 * p_tr);
        let turbulent = |dp: f64| dp.signum() * a_o * (2.0 * dp.abs() / (c0 * rho)).sqrt();
        for dp in [1e3 * p_tr, -1e4 * p_tr, 1e6 * p_tr] {
            let q = orifice_flow(a_o, c0, rho, p_tr, dp);
            // (1 + (p_tr/dp)^2)^(-1/4) = 1 - (p_tr/dp)^2 / 4 + ...
            let rel = (q / turbulent(dp) - 1.0).abs();
            assert!(rel <= 0.26 * (p_tr / dp).powi(2) + 1e-15, "{dp}: {rel:e}");
        }
        let slope = a_o * (2.0 / (c0 * rho)).sqrt() / p_tr.sqrt();
        for dp in [1e-6 * p_tr, -1e-3 * p_tr] {
            let q = orifice_flow(a_o, c0, rho, p_tr, dp);
            assert!((q / (slope * dp) - 1.0).abs() < 1e-6, "{dp}");
        }
        assert_eq!(orifice_flow(a_o, c0, rho, p_tr, 0.0), 0.0);
    }

    #[test]
    fn orifice_by_hand_and_sign() {
        // paper values: Ap/Ao = (0.02/0.008)^2 = 6.25; 0.5*3*900*6.25^2 = 52734.375 Pa/(m/s)^2
        let a_p = std::f64::consts::PI * 0.02f64.powi(2);
        let a_o = std::f64::consts::PI * 0.008f64.powi(2);
        assert!(close(
            orifice_pressure_drop(3.0, 900.0, a_p, a_o, 1.0),
            52734.375,
            1e-12
        ));
        assert!(close(
            orifice_pressure_drop(3.0, 900.0, a_p, a_o, -0.5),
            -52734.375 * 0.25,
            1e-12
        ));
        assert_eq!(orifice_pressure_drop(3.0, 900.0, a_p, a_o, 0.0), 0.0);
    }

    #[test]
    fn gas_by_hand() {
        let a_p = std::f64::consts::PI * 0.02f64.powi(2);
        assert!(close(
            gas_pressure(1000.0, 7.63e-5, a_p, 1.4, 0.0),
            1000.0,
            1e-15
        ));
        // at full stroke: V = 7.63e-5 - 1.2566e-3*0.023 = 4.7398e-5
        let v = 7.63e-5 - a_p * 0.023;
        let p = 1000.0 * (7.63e-5 / v).powf(1.4);
        assert!(close(
            gas_pressure(1000.0, 7.63e-5, a_p, 1.4, 0.023),
            p,
            1e-14
        ));
        assert!(p > 1900.0 && p < 2000.0, "{p}");
        // energy derivative is p1 A_p
        let s = 0.01;
        let e = |s| gas_energy(1000.0, 7.63e-5, a_p, 1.4, s);
        let de = (e(s + 1e-7) - e(s - 1e-7)) / 2e-7;
        assert!(close(
            de,
            gas_pressure(1000.0, 7.63e-5, a_p, 1.4, s) * a_p,
            1e-7
        ));
        assert_eq!(e(0.0), 0.0);
    }

    #[test]
    fn bistable_by_hand() {
        let (k, w, h) = (7022.0, 0.030, 0.0125);
        // stable and unstable points
        assert!(bistable_force(k, w, h, 0.0).abs() < 1e-12);
        assert!(bistable_force(k, w, h, h).abs() < 1e-12);
        assert!(bistable_force(k, w, h, 2.0 * h).abs() < 1e-12);
        // preload at x = e = 1 mm: 2*7022*0.0115*(0.0325/sqrt(0.0009+0.0115^2) - 1) ~ 1.87 N
        let f = bistable_force(k, w, h, 0.001);
        let l0 = (w * w + h * h).sqrt();
        let hand = 2.0 * 7022.0 * 0.0115 * (l0 / (0.0009f64 + 0.0115 * 0.0115).sqrt() - 1.0);
        assert!(close(f, hand, 1e-14));
        assert!((f - 1.87).abs() < 0.01, "{f}");
        // pushing forward before the apex, backward after it (snap-through)
        assert!(bistable_force(k, w, h, 0.005) > 0.0);
        assert!(bistable_force(k, w, h, 0.020) < 0.0);
        // symmetric: holds the tool on the back stop with the same force (x = 2h - e)
        assert!(close(bistable_force(k, w, h, 2.0 * h - 0.001), -f, 1e-12));
        // snap force: the largest forward force between 0 and h is about 5.4 N
        let fmax = (0..1000)
            .map(|i| bistable_force(k, w, h, h * i as f64 / 1000.0))
            .fold(0.0, f64::max);
        assert!((fmax - 5.4).abs() < 0.1, "{fmax}");
        // energy derivative is the force
        let x = 0.007;
        let de = (bistable_energy(k, w, h, x + 1e-8) - bistable_energy(k, w, h, x - 1e-8)) / 2e-8;
        assert!(close(de, bistable_force(k, w, h, x), 1e-6));
    }

    #[test]
    fn friction_sign() {
        // pushed back (sd > 0): friction on the tool points forward
        assert_eq!(tool_friction(2.0, 0.5, 0.4, 1.0), 2.2);
        assert_eq!(tool_friction(2.0, 0.5, -0.4, -1.0), -2.2);
        assert_eq!(tool_friction(0.0, 0.5, 0.0, 0.0), 0.0);
    }

    #[test]
    fn preload_equilibrium_by_hand() {
        // hydraulic paper values: k_e (-s0)^1.5 = p1(s0) A_p, p1 close to 1000 Pa.
        let a_p = std::f64::consts::PI * 0.02f64.powi(2);
        let pre = |s: f64| gas_pressure(1000.0, 7.63e-5, a_p, 1.4, s) * a_p;
        let s0 = preload_equilibrium(0.6e6, pre);
        assert!(s0 < 0.0);
        assert!(close(0.6e6 * (-s0).powf(1.5), pre(s0), 1e-13));
        // (1.2566/0.6e6)^(2/3) ~ 1.64e-4 m
        assert!((s0 + 1.637e-4).abs() < 1e-6, "{s0}");
        // no preload, no penetration
        assert_eq!(preload_equilibrium(0.6e6, |_| 0.0), 0.0);
    }

    #[test]
    fn robot_profile_kinks() {
        let mut r = RobotProfile::new(1.0, 10.0, Some(10.0));
        assert_eq!(r.t_cruise, Some(0.1));
        assert_eq!(r.on_time(0.1), Some("robot_cruising"));
        let (x, v, a) = r.current().at(0.1);
        assert!(close(x, 0.05, 1e-15) && v == 1.0 && a == 0.0);
        let t_stop = r.brake(0.2);
        assert!(close(t_stop, 0.3, 1e-15));
        assert_eq!(r.on_time(t_stop), Some("robot_stopped"));
        let (x, v, _) = r.segment_at(0.5).at(0.5);
        // 0.05 + 0.1 (cruise) + 0.05 (brake: v^2 / 2a) = 0.2
        assert!(close(x, 0.2, 1e-14) && v == 0.0);
        // lookup of the past
        assert_eq!(r.segment_at(0.05).phase, Phase::Accelerating);
        assert_eq!(r.segment_at(0.25).phase, Phase::Braking);
        assert!(r.stopped());
    }
}
