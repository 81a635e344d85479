//! A scene assembled into an ODE system holding only the parts it names.
//!
//! State layout (SPEC section 6, computed at run time; [`Layout`]):
//! - tool `x_t, v_t` (hydraulic and bistable only: the rigid tool is the flange),
//! - compressible liquid `p_m, V_x` (hydraulic with `hydraulic.bulk_modulus > 0` only),
//! - object `x_p, v_p` (when `object.enabled`),
//! - energy ledger quadratures (when `energy.ledger`): robot work, orifice dissipation
//!   (hydraulic), tool friction dissipation (hydraulic, bistable), contact damping dissipation
//!   (whenever a contact exists), plane friction dissipation (`object.plane_friction > 0`),
//! - the liquid's compression energy (ledger on, compressible liquid),
//! - `int F_c dt` (only with plane friction: the robot impulse then needs it; otherwise the
//!   impulse follows exactly from momentum, `int F_r dt = -(m_t dv_t + m_p dv_p)`).
//!
//! The robot is prescribed (not a state). Discrete regimes (contact on/off per contact, tool
//! stuck or slipping, object stuck or sliding, sensor switched, robot phase) change only in
//! event and time-stop handlers; the right-hand side is smooth within a regime.
//!
//! Events (only those the scene needs are assembled): sensor `s - s_sensor` (rising, once),
//! tool-object penetration `x_t - x_p`, forward stop penetration `-s`, back stop penetration
//! `s - L`, tool stick/slip (`sd` while slipping, `d (1 + 1e-9) - |F_static|` while stuck;
//! only with `tool.dry_friction > 0`), object stick/slip (`v_p` while sliding,
//! `mu m_p g (1 + 1e-9) - F_c` while stuck; only with plane friction). Robot kinks are time
//! stops. The position and speed events tell the integrator how far they can stray inside a
//! step (`event_chord_bound`), so quiet steps are not sampled inside.
//!
//! Peaks (`|F_r|`, `F_c`, stroke `s`) are sampled at every step's end, and at three interior
//! points of its dense output where a new peak is possible (`observe_step`); the step holding
//! the largest sample keeps five nodes of its dense output (a degree-4 polynomial, so they
//! reproduce it exactly) and the peak inside it (or just after it, in the next step, when the
//! largest sample is the step's end) is located once, at the end of the run, by Brent's search
//! (`peaks.rs`).

use crate::config::{Module, RobotStart, Scene};
use crate::gas_law::GasLaw;
use crate::peaks::{rival_window, PeakCandidate, PeakStep, K, MAX_DYNAMIC, TIE};
use crate::physics::{self, Phase, RobotProfile, Segment, GRAVITY};
use crate::trajectory::{EventLogEntry, TrajectoryPoint};
use cushion_ode::{Control, Direction, EventAction, OdeSystem, State, Step, MAX_EVENTS};

/// Where each part of the state lives (`None`: absent).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    /// Number of states.
    pub n: usize,
    pub tool: Option<usize>,
    pub object: Option<usize>,
    pub work: Option<usize>,
    pub d_orifice: Option<usize>,
    pub d_friction: Option<usize>,
    pub d_contact: Option<usize>,
    pub d_plane: Option<usize>,
    pub contact_impulse: Option<usize>,
    /// Compressible liquid (SPEC section 6): `p_m` and the volume moved through the orifice.
    pub liquid: Option<usize>,
    /// Energy stored by compressing the liquid (ledger, with `liquid`).
    pub e_liquid: Option<usize>,
}

impl Layout {
    pub fn of(scene: &Scene) -> Layout {
        let mut l = Layout::default();
        let mut n = 0;
        let mut take = |k: usize| {
            let i = n;
            n += k;
            Some(i)
        };
        let rigid = scene.module == Module::Rigid;
        let obj = scene.object.enabled;
        let plane = obj && scene.object.plane_friction > 0.0;
        let liquid = scene.module == Module::Hydraulic && scene.hydraulic.bulk_modulus > 0.0;
        if !rigid {
            l.tool = take(2);
        }
        if liquid {
            l.liquid = take(2);
        }
        if obj {
            l.object = take(2);
        }
        if scene.energy.ledger {
            l.work = take(1);
            if scene.module == Module::Hydraulic {
                l.d_orifice = take(1);
            }
            if !rigid {
                l.d_friction = take(1);
            }
            if !rigid || obj {
                l.d_contact = take(1);
            }
            if plane {
                l.d_plane = take(1);
            }
            if liquid {
                l.e_liquid = take(1);
            }
        }
        if plane {
            l.contact_impulse = take(1);
        }
        l.n = n;
        l
    }
}

/// The numbers of a scene the right-hand side needs, SI.
#[derive(Clone, Debug)]
pub(crate) struct Params {
    pub module: Module,
    pub has_object: bool,
    pub m_t: f64,
    pub m_p: f64,
    pub s_sensor: f64,
    pub b: f64,
    pub d: f64,
    pub k_c: f64,
    pub chi_c: f64,
    pub mu_n: f64,
    pub stroke: f64,
    pub k_e: f64,
    pub chi_e: f64,
    pub a_p: f64,
    pub a_o: f64,
    pub c0: f64,
    pub rho: f64,
    pub p10: f64,
    pub v_g0: f64,
    pub kappa: f64,
    pub k_b: f64,
    pub w: f64,
    pub h: f64,
    pub e: f64,
    pub dead_time: f64,
    /// Lower bound of the main chamber pressure (`None`: no cavitation model).
    pub p_cav: Option<f64>,
    /// Liquid bulk modulus (Pa) and main chamber volume at `s = 0` (m^3), compressible model.
    pub beta: f64,
    pub v_m0: f64,
}

/// The discrete state of the run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Regime {
    pub detected: bool,
    pub obj_contact: bool,
    pub fwd: bool,
    pub back: bool,
    pub tool_stuck: bool,
    /// Sign of `sd` while slipping (with dry friction).
    pub tool_dir: f64,
    pub obj_stuck: bool,
    /// The main chamber sits at the cavitation pressure.
    pub cavitating: bool,
    /// In contact, but its force has fallen to zero before the bodies part (fast restitution:
    /// `k + chi dd < 0`): the object contact; the end-stop in contact (at most one is).
    pub obj_released: bool,
    pub stop_released: bool,
}

/// Everything at one instant: kinematics (m, m/s, m/s^2), pressures (Pa), forces (N, + along
/// +x unless said otherwise), and the ledger's power terms (W).
#[derive(Clone, Copy, Debug, Default)]
pub struct Eval {
    pub x_r: f64,
    pub v_r: f64,
    pub a_r: f64,
    pub x_t: f64,
    pub v_t: f64,
    pub a_t: f64,
    pub x_p: f64,
    pub v_p: f64,
    pub a_p: f64,
    pub s: f64,
    pub sd: f64,
    /// Gas pressure (NaN without gas) and orifice pressure drop.
    pub p1: f64,
    pub dp: f64,
    /// Module force on the tool (`p_m A_p` or `F_b`).
    pub f_module: f64,
    /// Friction on the tool (static while stuck).
    pub f_f: f64,
    /// Magnitudes of the stop forces (forward stop pushes the tool back, back stop forward).
    pub f_fwd: f64,
    pub f_back: f64,
    /// Tool-object contact force (>= 0).
    pub f_c: f64,
    /// Total module force on the tool `G`; the force on the robot is `-G`.
    pub g: f64,
    pub f_r: f64,
    /// Plane friction on the object.
    pub f_plane: f64,
    pub p_work: f64,
    pub p_orifice: f64,
    pub p_friction: f64,
    pub p_contact: f64,
    pub p_plane: f64,
    /// Compressible model: flow through the orifice (m^3/s), `dp_m/dt` (Pa/s), and the power
    /// stored in the liquid (W).
    pub flow: f64,
    pub dp_m: f64,
    pub p_liquid: f64,
}

/// The flange and tool kinematics every event function starts from, computed once per
/// `events` call: flange `x_r` (m), `v_r` (m/s) on the current robot segment `seg`, tool `x_t`,
/// `v_t` (the flange itself for the rigid module).
struct EventKinematics<'a> {
    seg: &'a Segment,
    x_r: f64,
    v_r: f64,
    x_t: f64,
    v_t: f64,
}

impl<'a> EventKinematics<'a> {
    #[inline(always)]
    fn at(m: &'a Model, t: f64, y: &[f64]) -> EventKinematics<'a> {
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

/// Penetration (m) at which a contact begins; it ends at zero (see `event_value`). Its force
/// there, `k 1e-21`, is below 1e-15 N for the stiffnesses of the paper.
const CONTACT_HYSTERESIS: f64 = 1e-14;

/// Relative margin by which the holding force must exceed the friction limit for a stuck tool
/// or object to slip. A part sticks with a holding force just under the limit; its stuck value
/// is then constant only up to rounding (a few ulp of the forces it is the difference of), and
/// without the margin that noise could set off a slip a moment later and a stick right after
/// (seen with the tool settled at `|F_f| = d` to 4e-13).
const STICK_HYSTERESIS: f64 = 1e-9;

/// Speed (m/s) past zero at which a slipping part's stick test runs: its event function is
/// its slip speed plus this on the side it slips to (the tool: `sd + dir 1e-12`; the object,
/// which slides forward only: `v_p + 1e-12`). A slip begins at a speed of zero, and a function
/// that starts a step at exactly zero never fires there; without the margin, a reverse slip
/// that turns back within the step after a failed stick test was invisible, and the tool went
/// on slipping with its friction pushing instead of braking, until its speed next passed zero
/// (`tests/runs.rs`: the object then left up to 2.5e-3 m/s too fast at rtol 1e-8).
const SLIP_HYSTERESIS: f64 = 1e-12;

/// Relative margin (of `k`) by which `k + chi dd` must rise above zero for a released contact
/// to push again (see `release_value`).
const RELEASE_HYSTERESIS: f64 = 1e-12;

const EV_SENSOR: u8 = 0;
const EV_OBJECT: u8 = 1;
const EV_FWD: u8 = 2;
const EV_BACK: u8 = 3;
const EV_TOOL_STICK: u8 = 4;
const EV_OBJ_STICK: u8 = 5;
const EV_CAVITATION: u8 = 6;
const EV_OBJ_RELEASE: u8 = 7;
const EV_STOP_RELEASE: u8 = 8;

/// Which event functions a scene has. [`EventSet::visit`] lists their kinds in one fixed order,
/// the order of `Model::events` (their indices for the integrator).
#[derive(Clone, Copy, Debug)]
struct EventSet {
    /// Sensor, both end-stops and the stop release (hydraulic and bistable).
    tool: bool,
    /// Tool-object contact and its release.
    object: bool,
    /// Stick and slip of the tool (`tool.dry_friction > 0`).
    tool_stick: bool,
    /// Stick and slip of the object (plane friction).
    object_stick: bool,
    cavitation: bool,
}

impl EventSet {
    /// Call `f` with each kind the scene has, in index order. Inlined, each call's kind is a
    /// constant, so `f` can resolve its `match` on the kind at compile time: evaluating the
    /// functions this way takes a fixed series of branches that go the same way for the whole
    /// run, where a loop over `events` took an indirect jump per function to a different place
    /// each time.
    #[inline(always)]
    fn visit(&self, mut f: impl FnMut(u8)) {
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

/// Peaks and counts gathered along the run.
#[derive(Clone, Debug)]
pub(crate) struct Metrics {
    pub t_detect: Option<f64>,
    pub peak_fr: f64,
    pub t_peak_fr: f64,
    pub peak_fc: f64,
    pub max_stroke: f64,
    pub object_impacts: u32,
    pub fwd_impacts: u32,
    pub back_impacts: u32,
    pub back_hit: bool,
    /// Largest sampled gas pressure (compressible model; the lumped one uses `p1(max_stroke)`).
    pub max_p1: f64,
}

/// The ODE system of one scene.
pub struct Model {
    pub(crate) p: Params,
    /// The hydraulic module's gas law (`gas_law.rs`; of the volume moved through the orifice
    /// with a compressible liquid).
    gas: GasLaw,
    pub layout: Layout,
    pub(crate) regime: Regime,
    /// The regime in force during the step being reported to `on_step`.
    step_regime: Regime,
    pub(crate) robot: RobotProfile,
    pub(crate) pending_brake: Option<f64>,
    events: [u8; MAX_EVENTS],
    n_events: usize,
    /// The kinds of `events`, as flags: the event functions are evaluated by visiting them in
    /// `events`' order with each kind a constant (`EventSet::visit`).
    event_set: EventSet,
    pub(crate) metrics: Metrics,
    pub(crate) log: Vec<EventLogEntry>,
    /// Recorded trajectory points (when asked).
    pub(crate) record: Option<Vec<TrajectoryPoint>>,
    pub(crate) sample_interval: Option<f64>,
    /// Next uniform sample time, `(n_samples + 1) * sample_interval` (no accumulated rounding).
    pub(crate) next_sample: f64,
    n_samples: u64,
    pub(crate) early_end: Option<f64>,
    /// The tool's ringing in closed form after an early end (`ringing_tail.rs`).
    pub(crate) ringing_tail: Option<crate::ringing_tail::RingingTail>,
    pub(crate) ringing_tail_enabled: bool,
    /// Largest ringing amplitude for the closed form, fraction of the stop's depth.
    pub(crate) ringing_max_amplitude: f64,
    /// Error the closed form may leave in the robot impulse, N s: rtol times the momentum scale
    /// `(m_t + m_p) v_max`.
    pub(crate) ringing_impulse_tolerance: f64,
    /// No ringing-tail check before this time.
    pub(crate) next_ringing_check: f64,
    /// Linearisations about the stop's equilibrium, by robot acceleration and holding stop.
    pub(crate) ringing_cache: Vec<(f64, bool, crate::ringing_tail::Linearisation)>,
    fr_peak: PeakCandidate,
    fc_peak: PeakCandidate,
    s_peak: PeakCandidate,
    /// `F_r, F_c, s, sd` at the end of the last step.
    last_sample: Option<(f64, f64, f64, f64)>,
    /// Steps still to sample in full (set by events and time stops).
    force_sample: u8,
    /// The next step begins where `F_r` jumps (a robot kink under a rigid or stuck tool, a stick
    /// or slip of the tool): its start is sampled too, on its own side of the jump.
    sample_start: bool,
    /// The largest `|F_r|` of those samples, with its time (s) and sign (N).
    fr_after_jump: Option<(f64, f64)>,
    early_end_enabled: bool,
    pub(crate) t_end: f64,
    settle_v: f64,
    settle_a: f64,
    /// The solver's tolerances (for the tool's rest while the robot cruises, `resting.rs`).
    pub(crate) atol: f64,
    pub(crate) rtol: f64,
    /// The stroke the tool rests at after a settled early end while the robot cruises (m).
    pub(crate) rest_stroke: Option<f64>,
    /// The initial state (the preload equilibrium), in the order of `layout`.
    pub y0: Vec<f64>,
}

impl Model {
    /// Assemble a (validated) scene; the initial state is the static preload equilibrium.
    pub fn new(scene: &Scene) -> Model {
        let layout = Layout::of(scene);
        let h = &scene.hydraulic;
        let bi = &scene.bistable;
        let p = Params {
            module: scene.module,
            has_object: scene.object.enabled,
            m_t: scene.tool.mass,
            m_p: scene.object.mass,
            s_sensor: scene.tool.sensor_threshold,
            b: scene.tool.viscous_friction,
            d: scene.tool.dry_friction,
            k_c: scene.object.contact_stiffness,
            chi_c: scene.object.contact_damping,
            mu_n: scene.object.plane_friction * scene.object.mass * GRAVITY,
            stroke: scene.stops.stroke,
            k_e: scene.stops.stiffness,
            chi_e: scene.stops.damping,
            a_p: scene.piston_area(),
            a_o: scene.orifice_area(),
            c0: h.loss_coefficient,
            rho: h.liquid_density,
            p10: h.gas_pressure,
            v_g0: h.gas_volume,
            kappa: h.gas_exponent,
            k_b: bi.spring_stiffness,
            w: bi.half_span,
            h: bi.apex_rise,
            e: bi.offset,
            dead_time: scene.robot.dead_time,
            p_cav: (scene.module == Module::Hydraulic && h.cavitation && h.bulk_modulus == 0.0)
                .then_some(h.cavitation_pressure),
            beta: h.bulk_modulus,
            v_m0: h.chamber_volume,
        };
        let from_rest = match scene.robot.start {
            RobotStart::Cruising => None,
            RobotStart::Rest => Some(scene.robot.acceleration),
        };
        let robot = RobotProfile::new(
            scene.robot.approach_speed,
            scene.robot.brake_deceleration,
            from_rest,
        );
        let v0 = if from_rest.is_some() {
            0.0
        } else {
            scene.robot.approach_speed
        };

        // Static preload equilibrium on the forward stop.
        let s0 = match p.module {
            Module::Hydraulic => {
                let (p10, vg0, a_p, kappa) = (p.p10, p.v_g0, p.a_p, p.kappa);
                physics::preload_equilibrium(p.k_e, |s| {
                    physics::gas_pressure(p10, vg0, a_p, kappa, s) * a_p
                })
            }
            Module::Bistable => {
                let (k_b, w, hh, e) = (p.k_b, p.w, p.h, p.e);
                physics::preload_equilibrium(p.k_e, |s| physics::bistable_force(k_b, w, hh, s + e))
            }
            Module::Rigid => 0.0,
        };
        let mut y0 = vec![0.0; layout.n.max(1)];
        let x_t0 = -s0;
        if let Some(i) = layout.tool {
            y0[i] = x_t0;
            y0[i + 1] = v0;
        }
        if let Some(j) = layout.object {
            y0[j] = x_t0 + scene.object.gap;
            y0[j + 1] = 0.0;
        }
        if let Some(q) = layout.liquid {
            // at rest: the chamber at the gas pressure, the gas volume that of the lumped model
            y0[q] = physics::gas_pressure(p.p10, p.v_g0, p.a_p, p.kappa, s0);
            y0[q + 1] = p.a_p * s0;
        }
        let regime = Regime {
            detected: false,
            obj_contact: false,
            fwd: s0 < 0.0,
            back: false,
            tool_stuck: false,
            tool_dir: 0.0,
            obj_stuck: p.mu_n > 0.0,
            cavitating: false,
            obj_released: false,
            stop_released: false,
        };
        let event_set = EventSet {
            tool: p.module != Module::Rigid,
            object: p.has_object,
            tool_stick: p.module != Module::Rigid && p.d > 0.0,
            object_stick: p.has_object && p.mu_n > 0.0,
            cavitation: p.p_cav.is_some(),
        };
        let mut events = [0u8; MAX_EVENTS];
        let mut n_events = 0;
        event_set.visit(|e| {
            events[n_events] = e;
            n_events += 1;
        });
        let atol = scene.solver.atol;
        let gas_area = if layout.liquid.is_some() { 1.0 } else { p.a_p };
        let mut m = Model {
            gas: GasLaw::new(p.p10, p.v_g0, gas_area, p.kappa),
            p,
            layout,
            regime,
            step_regime: regime,
            robot,
            pending_brake: None,
            events,
            n_events,
            event_set,
            metrics: Metrics {
                t_detect: None,
                peak_fr: 0.0,
                t_peak_fr: 0.0,
                peak_fc: 0.0,
                max_stroke: s0,
                object_impacts: 0,
                fwd_impacts: 0,
                back_impacts: 0,
                back_hit: false,
                max_p1: f64::NEG_INFINITY,
            },
            log: Vec::new(),
            record: None,
            sample_interval: None,
            next_sample: 0.0,
            n_samples: 0,
            early_end: None,
            ringing_tail: None,
            ringing_tail_enabled: scene.solver.early_end && scene.solver.ringing_tail,
            ringing_max_amplitude: crate::ringing_tail::max_amplitude(scene.solver.rtol),
            ringing_impulse_tolerance: scene.solver.rtol
                * (scene.tool.mass
                    + if scene.object.enabled {
                        scene.object.mass
                    } else {
                        0.0
                    })
                * scene.robot.approach_speed,
            next_ringing_check: 0.0,
            ringing_cache: Vec::new(),
            fr_peak: PeakCandidate::default(),
            fc_peak: PeakCandidate::default(),
            s_peak: PeakCandidate::default(),
            last_sample: None,
            force_sample: 0,
            sample_start: false,
            fr_after_jump: None,
            early_end_enabled: scene.solver.early_end,
            t_end: scene.t_end,
            settle_v: 100.0 * atol,
            settle_a: 1000.0 * atol,
            atol,
            rtol: scene.solver.rtol,
            rest_stroke: None,
            y0: Vec::new(),
        };
        // Dry friction: the tool starts stuck if friction can hold it.
        if m.p.d > 0.0 && m.p.module != Module::Rigid {
            m.regime.tool_stuck = true;
            let e = m.eval(0.0, &y0, m.robot.current(), &m.regime);
            if e.f_f.abs() > m.p.d {
                m.regime.tool_stuck = false;
                m.regime.tool_dir = e.f_f.signum();
            }
        }
        m.step_regime = m.regime;
        let e0 = m.eval(0.0, &y0, m.robot.current(), &m.regime);
        m.metrics.peak_fr = e0.f_r;
        m.metrics.peak_fc = e0.f_c;
        let window = rival_window(m.rtol);
        m.fr_peak = PeakCandidate::starting_at(e0.f_r.abs(), window);
        m.fc_peak = PeakCandidate::starting_at(e0.f_c, window);
        m.s_peak = PeakCandidate::starting_at(s0, window);
        m.metrics.max_p1 = e0.p1;
        m.y0 = y0;
        m
    }

    /// Record the trajectory from now on (every step end, every event, and uniform samples).
    pub(crate) fn start_recording(&mut self, sample_interval: Option<f64>) {
        let p = self.point_at(0.0, &self.y0.clone());
        self.record = Some(vec![p]);
        self.sample_interval = sample_interval.filter(|dt| *dt > 0.0 && dt.is_finite());
        if let Some(dt) = self.sample_interval {
            self.next_sample = dt;
        }
    }

    /// Everything at `(t, y)` with robot segment `seg` and regime `r`.
    pub(crate) fn eval(&self, t: f64, y: &[f64], seg: &Segment, r: &Regime) -> Eval {
        self.eval_inline(t, y, seg, r)
    }

    /// [`Model::eval`], inlined into the hot callers (the right-hand side and the per-step
    /// samples): there the compiler keeps the fields in registers and drops the ones the
    /// caller never reads (the ledger's power terms when the ledger is off, the forces the
    /// right-hand side does not need), instead of filling and copying the whole struct.
    #[inline(always)]
    fn eval_inline(&self, t: f64, y: &[f64], seg: &Segment, r: &Regime) -> Eval {
        let p = &self.p;
        let (x_r, v_r, a_r) = seg.at(t);
        let mut e = Eval {
            x_r,
            v_r,
            a_r,
            p1: f64::NAN,
            x_p: f64::NAN,
            v_p: f64::NAN,
            a_p: f64::NAN,
            ..Eval::default()
        };
        let rigid = p.module == Module::Rigid;
        let mut f_stop = 0.0;
        if let Some(i) = self.layout.tool {
            e.x_t = y[i];
            e.v_t = y[i + 1];
            e.s = x_r - e.x_t;
            e.sd = v_r - e.v_t;
            if r.fwd {
                let d = -e.s;
                e.f_fwd = contact_force(p.k_e, p.chi_e, d, -e.sd, r.stop_released);
                e.p_contact += (e.f_fwd - p.k_e * pos15(d)) * (-e.sd);
            }
            if r.back {
                let d = e.s - p.stroke;
                e.f_back = contact_force(p.k_e, p.chi_e, d, e.sd, r.stop_released);
                e.p_contact += (e.f_back - p.k_e * pos15(d)) * e.sd;
            }
            f_stop = e.f_back - e.f_fwd;
            match p.module {
                Module::Hydraulic if self.layout.liquid.is_some() => {
                    // compressible liquid: p_m is a state; the orifice passes the flow its
                    // pressure drop allows, dp = 0.5 c0 rho (Q/A_o)^2 sgn(Q)
                    let q = self.layout.liquid.unwrap_or(0);
                    let (p_m, v_x) = (y[q], y[q + 1]);
                    e.p1 = self.gas.pressure(v_x);
                    e.dp = p_m - e.p1;
                    e.flow = e.dp.signum() * p.a_o * (2.0 * e.dp.abs() / (p.c0 * p.rho)).sqrt();
                    let v_m = p.v_m0 - p.a_p * e.s;
                    e.dp_m = p.beta / v_m * (p.a_p * e.sd - e.flow);
                    e.f_module = p_m * p.a_p;
                    e.p_orifice = e.dp * e.flow;
                    e.p_liquid = p_m * (p.a_p * e.sd - e.flow);
                }
                Module::Hydraulic => {
                    e.p1 = self.gas.pressure(e.s);
                    e.dp = physics::orifice_pressure_drop(p.c0, p.rho, p.a_p, p.a_o, e.sd);
                    if r.cavitating {
                        // the liquid column tears: the chamber holds p_cav, the orifice
                        // carries p_cav - p1
                        e.dp = p.p_cav.unwrap_or(0.0) - e.p1;
                    }
                    e.f_module = (e.p1 + e.dp) * p.a_p;
                    e.p_orifice = e.dp * p.a_p * e.sd;
                }
                Module::Bistable => {
                    e.f_module = physics::bistable_force(p.k_b, p.w, p.h, e.s + p.e);
                }
                Module::Rigid => {}
            }
        } else {
            // Rigid: the tool is the flange.
            e.x_t = x_r;
            e.v_t = v_r;
        }
        if let Some(j) = self.layout.object {
            e.x_p = y[j];
            e.v_p = y[j + 1];
            if r.obj_contact {
                let d = e.x_t - e.x_p;
                let dd = e.v_t - e.v_p;
                e.f_c = contact_force(p.k_c, p.chi_c, d, dd, r.obj_released);
                e.p_contact += (e.f_c - p.k_c * pos15(d)) * dd;
            }
        }
        if rigid {
            e.a_t = a_r;
            e.g = p.m_t * a_r + e.f_c;
        } else if r.tool_stuck {
            e.a_t = a_r;
            e.g = p.m_t * a_r + e.f_c;
            e.f_f = e.g - e.f_module - f_stop;
            e.p_friction = e.f_f * e.sd;
        } else {
            e.f_f = physics::tool_friction(p.d, p.b, e.sd, r.tool_dir);
            e.g = e.f_module + e.f_f + f_stop;
            e.a_t = (e.g - e.f_c) / p.m_t;
            e.p_friction = e.f_f * e.sd;
        }
        e.f_r = -e.g;
        e.p_work = e.g * v_r;
        if self.layout.object.is_some() {
            if p.mu_n > 0.0 {
                if r.obj_stuck {
                    e.a_p = 0.0;
                    e.f_plane = -e.f_c;
                } else {
                    e.f_plane = -p.mu_n;
                    e.a_p = (e.f_c + e.f_plane) / p.m_p;
                    e.p_plane = p.mu_n * e.v_p;
                }
            } else {
                e.a_p = e.f_c / p.m_p;
            }
        }
        e
    }

    /// The trajectory point at `t` (robot segment looked up by time, current regime).
    pub(crate) fn point_at(&self, t: f64, y: &[f64]) -> TrajectoryPoint {
        let seg = *self.robot.segment_at(t);
        let e = self.eval(t, y, &seg, &self.regime);
        to_point(t, &e)
    }

    fn log_event(&mut self, name: &str, t: f64, y: &[f64]) {
        let seg = *self.robot.current();
        let e = self.eval(t, y, &seg, &self.regime);
        let point = to_point(t, &e);
        if let Some(rec) = self.record.as_mut() {
            rec.push(point);
        }
        self.log.push(EventLogEntry {
            t,
            name: name.to_string(),
            point,
        });
    }

    fn brake_now(&mut self, t: f64, y: &[f64], ctl: &mut Control) {
        let t_stop = self.robot.brake(t);
        ctl.add_time_stop(t_stop);
        self.log_event("brake", t, y);
    }

    /// Event function `kind` at `(t, y)`, from the flange and tool kinematics `k` at that point
    /// (computed once per `events` call and shared by every event function).
    #[inline(always)]
    fn event_value(&self, kind: u8, t: f64, y: &[f64], k: &EventKinematics) -> f64 {
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
    fn event_straying(&self, kind: u8, h: f64, dev: &[f64]) -> Option<f64> {
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

    fn handle_event(&mut self, kind: u8, t: f64, y: &mut [f64], ctl: &mut Control) -> EventAction {
        self.force_sample = 2;
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
            EV_OBJECT => {
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
            EV_OBJ_RELEASE => {
                self.regime.obj_released = !self.regime.obj_released;
                EventAction::Restart
            }
            EV_STOP_RELEASE => {
                self.regime.stop_released = !self.regime.stop_released;
                EventAction::Restart
            }
            EV_FWD => {
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
            EV_BACK => {
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
            EV_TOOL_STICK => {
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
                        self.regime.tool_dir = e.f_f.signum();
                    }
                }
                EventAction::Restart
            }
            EV_OBJ_STICK => {
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

    /// Whether nothing can change any more after `(t, y)`: the robot stands, or cruises with no
    /// brake before `t_end` (its sensor never switched, or the dead time ends after the run); the
    /// tool has settled (robot standing: stuck, or relative speed and acceleration at the
    /// tolerance's level; robot cruising: stuck short of the sensor, or at rest on its stop,
    /// `resting.rs`); and the object is out of contact and either free and not slower than the
    /// tool (nor, while the robot cruises, than the robot, which the resting tool rides with) or,
    /// with the robot standing, stuck on the plane. Then the run may end early
    /// with its final values extrapolated exactly. Failing that, the run may still end if only
    /// the tool's small ringing on its stop is left, written in closed form
    /// (`ringing_tail.rs`).
    pub(crate) fn can_end_early(&mut self, t: f64, y: &[f64]) -> bool {
        let stopped = self.robot.stopped();
        if !(self.early_end_enabled
            && t < self.t_end
            && (stopped || self.cruising_to_end())
            && !self.regime.obj_contact)
        {
            return t < self.t_end && self.try_ringing_tail(t, y);
        }
        let seg = *self.robot.current();
        // a cruising robot's run goes on while it may reach the object again (before the
        // impact, always): found from the state, without the physics. The tool that may end
        // here rides on with the robot, so the object must outrun the robot as well as the
        // tool's speed of the moment, which a tool at rest on its stop may have a little below
        // the robot's (by up to its rest tolerance)
        if !stopped {
            let v_r = seg.at(t).1;
            let v_t = self.layout.tool.map_or(v_r, |i| y[i + 1]);
            if !self.object_outruns(y, v_t.max(v_r)) {
                return self.try_ringing_tail(t, y);
            }
        }
        let e = self.eval(t, y, &seg, &self.regime);
        // (for a cruising robot, the object was found out of reach above)
        let object_done = !stopped
            || match self.layout.object {
                None => true,
                Some(_) => {
                    if self.p.mu_n > 0.0 {
                        self.regime.obj_stuck
                    } else {
                        e.v_p >= e.v_t.max(0.0)
                    }
                }
            };
        let tool_settled = match self.layout.tool {
            None => true,
            Some(_) if stopped => {
                self.regime.tool_stuck
                    || (e.sd.abs() <= self.settle_v && e.a_t.abs() <= self.settle_a)
            }
            // the robot cruises on: stuck (short of the sensor, or it would have switched; and
            // no compressible liquid still flowing through the orifice), or at rest on a stop
            Some(_) if self.regime.tool_stuck => self.layout.liquid.is_none(),
            Some(_) => {
                self.rest_stroke = self.rest_on_stop(t, y, &seg, &e);
                self.rest_stroke.is_some()
            }
        };
        (tool_settled && object_done) || self.try_ringing_tail(t, y)
    }

    /// The object can never be touched again by a robot that cruises on: absent, or free (no
    /// plane friction) and not slower than `v` (m/s) in the state `y`.
    pub(crate) fn object_outruns(&self, y: &[f64], v: f64) -> bool {
        match self.layout.object {
            None => true,
            Some(j) => self.p.mu_n == 0.0 && y[j + 1] >= v.max(0.0),
        }
    }

    /// The robot cruises and will not brake before `t_end`: its sensor has not switched (it may
    /// yet), or the dead time ends after the run.
    pub(crate) fn cruising_to_end(&self) -> bool {
        self.robot.current().phase == Phase::Cruising
            && self.pending_brake.is_none_or(|tb| tb >= self.t_end)
    }

    /// Refine the peaks of `|F_r|`, `F_c` and `s` inside the steps that hold their largest
    /// samples (`peaks.rs`), on the step's dense output (rebuilt from its five nodes).
    pub(crate) fn refine_peaks(&mut self) {
        let n = self.layout.n.clamp(1, MAX_STATES);
        let (fr, fc, s) = (
            std::mem::take(&mut self.fr_peak),
            std::mem::take(&mut self.fc_peak),
            std::mem::take(&mut self.s_peak),
        );
        let at = |c: &PeakStep, t: f64| self.eval(t, &c.state_at(t)[..n], &c.seg, &c.regime);
        let m = &self.metrics;
        // the signed force at the refined peak, from the step that holds it (an earlier peak of
        // the same height may lie below the largest sample by rounding: `TIE`)
        let peak_fr = fr
            .locate(|c, t| at(c, t).f_r.abs(), m.peak_fr.abs())
            .filter(|&(_, v, _)| v > m.peak_fr.abs() * (1.0 - TIE))
            .map(|(t, _, c)| (t, at(c, t).f_r));
        let peak_fc = fc.locate(|c, t| at(c, t).f_c, m.peak_fc).map(|p| p.1);
        let max_stroke = s.locate(|c, t| at(c, t).s, m.max_stroke).map(|p| p.1);
        if let Some((t, f_r)) = peak_fr {
            self.metrics.peak_fr = f_r;
            self.metrics.t_peak_fr = t;
        }
        if let Some((t, f_r)) = self.fr_after_jump {
            if f_r.abs() > self.metrics.peak_fr.abs() {
                self.metrics.peak_fr = f_r;
                self.metrics.t_peak_fr = t;
            }
        }
        if let Some(v) = peak_fc {
            self.metrics.peak_fc = v;
        }
        if let Some(v) = max_stroke {
            self.metrics.max_stroke = v;
        }
    }

    fn observe_step<const N: usize>(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        let (t0, t1) = (step.t0, step.t1);
        let y1 = step.y1.as_slice();
        let seg = *self.robot.segment_at(0.5 * (t0 + t1));
        let r = self.step_regime;
        // Five nodes of the step's dense output (a polynomial of degree 4 in t, so these five
        // states reproduce it exactly); the physics is sampled at the four after t0.
        let n = self.layout.n.clamp(1, MAX_STATES);
        let tk = |k: usize| {
            if k == K {
                t1
            } else {
                t0 + (t1 - t0) * (k as f64 / K as f64)
            }
        };
        // the states the physics reads (the ledger's quadratures come after them)
        let dynamic = self
            .layout
            .work
            .or(self.layout.contact_impulse)
            .unwrap_or(n)
            .min(MAX_DYNAMIC);
        // a node: the leading `dynamic` states (a fixed-length loop: no call to memcpy)
        let lead = |yk: &State<N>| {
            let mut v = [0.0; MAX_DYNAMIC];
            for (j, vj) in v.iter_mut().enumerate().take(N.min(MAX_DYNAMIC)) {
                if j < dynamic {
                    *vj = yk[j];
                }
            }
            v
        };
        let node = |k: usize| match k {
            0 => lead(step.y0),
            K => lead(step.y1),
            _ => lead(&step.at(tk(k))),
        };
        let mut fr_best = (0usize, 0.0f64);
        let mut fc_best = (0usize, 0.0f64);
        let mut s_best = (0usize, f64::NEG_INFINITY);
        let mut p1_best = f64::NEG_INFINITY;
        let mut consider = |k: usize, e: &Eval| {
            if e.p1 > p1_best {
                p1_best = e.p1;
            }
            if e.f_r.abs() > fr_best.1.abs() {
                fr_best = (k, e.f_r);
            }
            if e.f_c > fc_best.1 {
                fc_best = (k, e.f_c);
            }
            if e.s > s_best.1 {
                s_best = (k, e.s);
            }
        };
        let e1 = self.eval_inline(t1, y1, &seg, &r);
        consider(K, &e1);
        if std::mem::take(&mut self.sample_start) {
            // Where the step begins, the force on a rigid or stuck tool jumps by `m_t` times
            // the jump of the robot's acceleration, and a stick or slip changes the friction:
            // the largest |F_r| may be the first value on this side, which no sample inside
            // the step sees (a rigid tool pressing an object when the robot stops: 17.71 N
            // reported for 17.80 N at rtol 1e-6). It is kept apart from the peak search: a
            // value at a jump is exact where it is.
            let f_r = self.eval_inline(t0, step.y0.as_slice(), &seg, &r).f_r;
            if self.fr_after_jump.is_none_or(|(_, f)| f_r.abs() > f.abs()) {
                self.fr_after_jump = Some((t0, f_r));
            }
        }
        // The interior is sampled only where a new peak is possible: near or above the force
        // peaks so far, where the stroke turns (its largest value lies in a step where `sd`
        // changes sign; while it rises, the step's end is its largest), and around events;
        // elsewhere the step's end suffices.
        let m = &self.metrics;
        let interior = match self.last_sample {
            None => true,
            Some((fr0, fc0, _, sd0)) => {
                self.force_sample > 0
                    || fr0.abs().max(e1.f_r.abs()) > 0.5 * m.peak_fr.abs()
                    || fc0.max(e1.f_c) > 0.5 * m.peak_fc
                    || (sd0 > 0.0 && e1.sd <= 0.0)
            }
        };
        // The nodes of a new peak candidate, computed at most once per step (below).
        let mut nodes: Option<[[f64; MAX_DYNAMIC]; K + 1]> = None;
        if interior {
            // the interior samples are the interior nodes
            let mut v = [[0.0; MAX_DYNAMIC]; K + 1];
            v[0] = node(0);
            v[K] = node(K);
            for (k, vk) in v.iter_mut().enumerate().take(K).skip(1) {
                let yk = step.at(tk(k));
                *vk = lead(&yk);
                let e = self.eval_inline(tk(k), yk.as_slice(), &seg, &r);
                consider(k, &e);
            }
            nodes = Some(v);
        }
        self.last_sample = Some((e1.f_r, e1.f_c, e1.s, e1.sd));
        if p1_best > self.metrics.max_p1 {
            self.metrics.max_p1 = p1_best;
        }
        self.force_sample = self.force_sample.saturating_sub(1);
        // A new largest sample: remember its step; the peak inside it is refined once, at the
        // end of the run (`refine_peaks`).
        let mut cand = |k: usize| PeakStep {
            ts: std::array::from_fn(tk),
            nodes: *nodes.get_or_insert_with(|| std::array::from_fn(node)),
            seg,
            regime: r,
            k,
        };
        // A largest sample at the previous step's end: the peak may lie in this step.
        for c in [&mut self.fr_peak, &mut self.fc_peak, &mut self.s_peak] {
            if c.wants_next() {
                c.follow(cand(0));
            }
        }
        let (v, end) = (fr_best.1.abs(), e1.f_r.abs());
        if self.fr_peak.observe(v, end, || cand(fr_best.0)) {
            self.metrics.peak_fr = fr_best.1;
            self.metrics.t_peak_fr = tk(fr_best.0);
        }
        if self.fc_peak.observe(fc_best.1, e1.f_c, || cand(fc_best.0)) {
            self.metrics.peak_fc = fc_best.1;
        }
        if self.layout.tool.is_some() && self.s_peak.observe(s_best.1, e1.s, || cand(s_best.0)) {
            self.metrics.max_stroke = s_best.1;
        }
        if self.record.is_some() {
            let mut pts = Vec::new();
            if let Some(dt) = self.sample_interval {
                while self.next_sample < t1 {
                    let ts = self.next_sample;
                    let e = self.eval(ts, step.at(ts).as_slice(), &seg, &r);
                    pts.push(to_point(ts, &e));
                    self.n_samples += 1;
                    self.next_sample = (self.n_samples + 1) as f64 * dt;
                }
            }
            // the step's end: the same (t1, y1, seg, r) as e1
            pts.push(to_point(t1, &e1));
            if let Some(rec) = self.record.as_mut() {
                rec.extend(pts);
            }
        }
        // a stick or slip of the tool, or a slip that turns, changes its friction at once
        if self.regime.tool_stuck != r.tool_stuck || self.regime.tool_dir != r.tool_dir {
            self.sample_start = true;
        }
        self.step_regime = self.regime;

        // Early end: nothing can change any more.
        if self.can_end_early(t1, y1) {
            self.early_end = Some(t1);
            ctl.stop();
        }
    }
}

/// The largest state a scene can need (tool 2 + liquid 2 + object 2 + ledger 6 + contact
/// impulse 1).
pub const MAX_STATES: usize = 13;

/// Hunt–Crossley force of a contact (N, >= 0 while pushing), penetration `d` (m), its rate
/// `dd` (m/s): `d^1.5 (k + chi dd)` while it pushes, 0 once released. The clamp at zero of
/// `physics::hunt_crossley` is the release event here (`EV_*_RELEASE`): inside a step the law
/// stays smooth, and the step that reaches `k + chi dd = 0` is cut there.
#[inline(always)]
fn contact_force(k: f64, chi: f64, d: f64, dd: f64, released: bool) -> f64 {
    if released {
        0.0
    } else {
        pos15(d) * (k + chi * dd)
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

#[inline]
fn pos15(d: f64) -> f64 {
    if d > 0.0 {
        d * d.sqrt()
    } else {
        0.0
    }
}

pub(crate) fn to_point(t: f64, e: &Eval) -> TrajectoryPoint {
    TrajectoryPoint {
        t,
        x_r: e.x_r,
        v_r: e.v_r,
        x_t: e.x_t,
        v_t: e.v_t,
        x_p: e.x_p,
        v_p: e.v_p,
        s: e.s,
        p1: e.p1,
        f_c: e.f_c,
        f_r: e.f_r,
    }
}

impl<const N: usize> OdeSystem<N> for Model {
    #[inline]
    fn rhs(&self, t: f64, y: &State<N>) -> State<N> {
        let e = self.eval_inline(t, y.as_slice(), self.robot.current(), &self.regime);
        let l = &self.layout;
        let mut dy = State::<N>::zeros();
        if let Some(i) = l.tool {
            dy[i] = e.v_t;
            dy[i + 1] = e.a_t;
        }
        if let Some(j) = l.object {
            dy[j] = if self.regime.obj_stuck { 0.0 } else { e.v_p };
            dy[j + 1] = e.a_p;
        }
        if let Some(k) = l.work {
            dy[k] = e.p_work;
        }
        if let Some(k) = l.d_orifice {
            dy[k] = e.p_orifice;
        }
        if let Some(k) = l.d_friction {
            dy[k] = e.p_friction;
        }
        if let Some(k) = l.d_contact {
            dy[k] = e.p_contact;
        }
        if let Some(k) = l.d_plane {
            dy[k] = e.p_plane;
        }
        if let Some(k) = l.contact_impulse {
            dy[k] = e.f_c;
        }
        if let Some(q) = l.liquid {
            dy[q] = e.dp_m;
            dy[q + 1] = e.flow;
        }
        if let Some(k) = l.e_liquid {
            dy[k] = e.p_liquid;
        }
        dy
    }

    fn event_count(&self) -> usize {
        self.n_events
    }

    fn events(&self, t: f64, y: &State<N>, g: &mut [f64]) {
        let y = y.as_slice();
        let k = EventKinematics::at(self, t, y);
        let mut i = 0;
        self.event_set.visit(|kind| {
            if let Some(gi) = g.get_mut(i) {
                *gi = self.event_value(kind, t, y, &k);
            }
            i += 1;
        });
    }

    fn event(&self, i: usize, t: f64, y: &State<N>) -> f64 {
        let y = y.as_slice();
        let k = EventKinematics::at(self, t, y);
        self.event_value(self.events[i], t, y, &k)
    }

    fn event_chord_bound(&self, i: usize, t0: f64, t1: f64, dev: &State<N>) -> Option<f64> {
        let kind = *self.events.get(i)?;
        self.event_straying(kind, t1 - t0, dev.as_slice())
    }

    fn event_chord_bounds(&self, t0: f64, t1: f64, dev: &State<N>, bounds: &mut [f64]) {
        let dev = dev.as_slice();
        let mut i = 0;
        self.event_set.visit(|kind| {
            if let Some(b) = bounds.get_mut(i) {
                *b = self.event_straying(kind, t1 - t0, dev).unwrap_or(f64::NAN);
            }
            i += 1;
        });
    }

    fn event_direction(&self, i: usize) -> Direction {
        match self.events.get(i).copied() {
            Some(EV_SENSOR) => Direction::Rising,
            Some(EV_OBJECT) => {
                if self.regime.obj_contact {
                    Direction::Falling
                } else {
                    Direction::Rising
                }
            }
            Some(EV_FWD) => {
                if self.regime.fwd {
                    Direction::Falling
                } else {
                    Direction::Rising
                }
            }
            Some(EV_BACK) => {
                if self.regime.back {
                    Direction::Falling
                } else {
                    Direction::Rising
                }
            }
            Some(EV_CAVITATION) => {
                if self.regime.cavitating {
                    Direction::Rising
                } else {
                    Direction::Falling
                }
            }
            _ => Direction::Both,
        }
    }

    fn on_event(&mut self, i: usize, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        let kind = self.events[i];
        self.handle_event(kind, t, y.as_mut_slice(), ctl)
    }

    fn on_time_stop(&mut self, t: f64, y: &mut State<N>, ctl: &mut Control) -> EventAction {
        self.force_sample = 2;
        // the robot's acceleration jumps: so does the force on a tool that moves with it
        self.sample_start = self.p.module == Module::Rigid || self.regime.tool_stuck;
        if let Some(tb) = self.pending_brake {
            if (t - tb).abs() <= 1e-12 * (1.0 + tb.abs()) {
                self.pending_brake = None;
                self.brake_now(t, y.as_slice(), ctl);
                return EventAction::Continue;
            }
        }
        if let Some(name) = self.robot.on_time(t) {
            self.log_event(name, t, y.as_slice());
            if self.can_end_early(t, y.as_slice()) {
                self.early_end = Some(t);
                return EventAction::Stop;
            }
        }
        EventAction::Continue
    }

    fn on_step(&mut self, step: &Step<'_, N>, ctl: &mut Control) {
        self.observe_step(step, ctl);
    }
}
