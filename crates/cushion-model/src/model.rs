//! A scene assembled into an ODE system holding only the parts it names.
//!
//! State layout (`docs/model.md`, section "Scene and frames"; computed at run time, [`Layout`]):
//! - tool `x_t, v_t` (hydraulic and bistable only: the rigid tool is the flange),
//! - compressible liquid `p_m, V_x` (hydraulic with `hydraulic.bulk_modulus > 0` only),
//! - object `x_p, v_p` (when `object.enabled`),
//! - energy ledger quadratures (when `energy.ledger`): robot work, and the energy dissipated
//!   (whenever something dissipates: the orifice, the tool's friction, the contacts' damping,
//!   the plane's friction, in one state, as the ledger balances their sum),
//! - the liquid's compression energy (ledger on, compressible liquid),
//! - `int F_c dt` (only with plane friction: the robot impulse then needs it; otherwise the
//!   impulse follows exactly from momentum, `int F_r dt = -(m_t dv_t + m_p dv_p)`).
//!
//! The ledger's states and `int F_c dt` are quadratures: no rate reads them
//! ([`Layout::quadratures`]).
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
//! The model is the physics only. What observes a run (the peaks, the early end, the
//! trajectory) lives apart, in `observe.rs`, and `simulate` composes it with the model.
//!
//! Here: the layout, the scene's numbers and the assembly (`Model::new`). The rest, one idea a
//! file: `model/forces.rs` the physics at an instant, `model/events.rs` the event functions and
//! what each does, `model/ode_system.rs` the model as the integrator sees it,
//! `model/jacobian.rs` its derivatives for the implicit method.

mod events;
mod forces;
mod jacobian;
mod ode_system;

use crate::config::{Module, RobotStart, Scene};
use crate::gas_law::GasLaw;
use crate::physics::{self, RobotProfile, GRAVITY};
use crate::trajectory::EventLogEntry;
use cushion_ode::MAX_EVENTS;
use events::EventSet;
pub(crate) use forces::to_point;
pub use forces::Eval;

/// Where each part of the state lives (`None`: absent).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    /// Number of states.
    pub n: usize,
    pub tool: Option<usize>,
    pub object: Option<usize>,
    pub work: Option<usize>,
    /// Energy dissipated by the orifice, the tool's friction, the contacts' damping and the
    /// plane's friction (ledger). One state for their sum: the ledger balances the sum, and
    /// each more state costs every stage of every step.
    pub dissipated: Option<usize>,
    pub contact_impulse: Option<usize>,
    /// Compressible liquid (`docs/model.md`, section "Compressible liquid"): `p_m` and the volume
    /// moved through the orifice.
    pub liquid: Option<usize>,
    /// Energy stored by compressing the liquid (ledger, with `liquid`).
    pub e_liquid: Option<usize>,
    /// What each state's derivative is, by state (`Rate` as `u8`; the right-hand side gathers
    /// them in one pass instead of testing each part of the layout on every evaluation).
    pub(crate) rates: [u8; MAX_STATES],
}

/// The derivative of a state, as an index into the right-hand side's list of rates
/// (`model/ode_system.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Rate {
    ToolSpeed,
    ToolAcceleration,
    ChamberPressureChange,
    Flow,
    ObjectSpeed,
    ObjectAcceleration,
    RobotPower,
    DissipatedPower,
    LiquidPower,
    ContactForce,
    /// No state (the single placeholder of a scene with none).
    Zero,
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
            // The orifice or the tool's friction (hydraulic, bistable), a contact's damping.
            if !rigid || obj {
                l.dissipated = take(1);
            }
            if liquid {
                l.e_liquid = take(1);
            }
        }
        if plane {
            l.contact_impulse = take(1);
        }
        l.n = n;
        l.rates = [Rate::Zero as u8; MAX_STATES];
        let mut set = |at: Option<usize>, rate: Rate| {
            if let Some(i) = at {
                l.rates[i] = rate as u8;
            }
        };
        set(l.tool, Rate::ToolSpeed);
        set(l.tool.map(|i| i + 1), Rate::ToolAcceleration);
        set(l.liquid, Rate::ChamberPressureChange);
        set(l.liquid.map(|i| i + 1), Rate::Flow);
        set(l.object, Rate::ObjectSpeed);
        set(l.object.map(|i| i + 1), Rate::ObjectAcceleration);
        set(l.work, Rate::RobotPower);
        set(l.dissipated, Rate::DissipatedPower);
        set(l.e_liquid, Rate::LiquidPower);
        set(l.contact_impulse, Rate::ContactForce);
        l
    }

    /// How many states are quadratures: the ledger's energies and `int F_c dt`, integrals of
    /// the other states that no rate reads. The integrator's error norm averages over the other
    /// states (`cushion_ode::SolverOptions::quadratures`), so that the ledger, whose integrals
    /// are smooth where the motion is, barely changes the steps
    /// (`tests/model/runs.rs::the_ledger_barely_changes_the_steps`), and still limits them where the
    /// forces change while the states do not. None when every state is one (the rigid flange
    /// alone).
    pub fn quadratures(&self) -> usize {
        let q = [
            self.work,
            self.dissipated,
            self.e_liquid,
            self.contact_impulse,
        ]
        .iter()
        .filter(|i| i.is_some())
        .count();
        if q < self.n {
            q
        } else {
            0
        }
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
    /// Pressure difference where the compressible model's orifice turns laminar, Pa.
    pub p_transition: f64,
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

/// What the event handlers record besides the event log: the detection time (s) and the
/// impacts.
#[derive(Clone, Debug, Default)]
pub(crate) struct Metrics {
    pub t_detect: Option<f64>,
    pub object_impacts: u32,
    pub fwd_impacts: u32,
    pub back_impacts: u32,
    pub back_hit: bool,
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
    /// The last time stop was a kink of the robot's profile (`Model::time_stop`): the early
    /// end looks there whether anything is left to change.
    pub(crate) time_stop_was_kink: bool,
    events: [u8; MAX_EVENTS],
    n_events: usize,
    /// The kinds of `events`, as flags: the event functions are evaluated by visiting them in
    /// `events`' order with each kind a constant (`EventSet::visit`).
    event_set: EventSet,
    pub(crate) metrics: Metrics,
    pub(crate) log: Vec<EventLogEntry>,
    pub(crate) t_end: f64,
    /// The stroke of the static preload equilibrium the run starts in (m).
    pub(crate) preload_stroke: f64,
    /// The initial state (the preload equilibrium), in the order of `layout`.
    pub y0: Vec<f64>,
}

impl Params {
    /// The numbers of a (validated) scene, in the model's symbols.
    fn of(scene: &Scene) -> Params {
        let h = &scene.hydraulic;
        let bi = &scene.bistable;
        Params {
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
            v_m0: scene.main_chamber_volume(),
            p_transition: physics::orifice_transition_pressure(
                h.loss_coefficient,
                h.liquid_density,
                h.kinematic_viscosity,
                h.critical_reynolds,
                h.orifice_radius,
            ),
        }
    }

    /// The stroke `s0 <= 0` (m) of the static preload equilibrium on the forward stop, where
    /// the stop's elastic force balances the module's preload: the gas pressure on the piston,
    /// or the bistable springs' force. The rigid flange has no stroke.
    fn preload_stroke(&self) -> f64 {
        match self.module {
            Module::Hydraulic => {
                let (p10, vg0, a_p, kappa) = (self.p10, self.v_g0, self.a_p, self.kappa);
                physics::preload_equilibrium(self.k_e, |s| {
                    physics::gas_pressure(p10, vg0, a_p, kappa, s) * a_p
                })
            }
            Module::Bistable => {
                let (k_b, w, hh, e) = (self.k_b, self.w, self.h, self.e);
                physics::preload_equilibrium(self.k_e, |s| {
                    physics::bistable_force(k_b, w, hh, s + e)
                })
            }
            Module::Rigid => 0.0,
        }
    }

    /// Which event functions the scene needs, and their kinds in index order.
    fn event_functions(&self) -> (EventSet, [u8; MAX_EVENTS], usize) {
        let event_set = EventSet {
            tool: self.module != Module::Rigid,
            object: self.has_object,
            tool_stick: self.module != Module::Rigid && self.d > 0.0,
            object_stick: self.has_object && self.mu_n > 0.0,
            cavitation: self.p_cav.is_some(),
        };
        let mut events = [0u8; MAX_EVENTS];
        let mut n_events = 0;
        event_set.visit(|e| {
            events[n_events] = e;
            n_events += 1;
        });
        (event_set, events, n_events)
    }
}

/// The robot's speed profile, and the flange's speed at `t = 0` (at rest or cruising).
fn robot_at_start(scene: &Scene) -> (RobotProfile, f64) {
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
    (robot, v0)
}

/// The initial state, in the order of `layout`: the tool held on its forward stop at the
/// preload stroke `s0` and moving with the flange at `v0`, the object at rest `gap` ahead of
/// it, the liquid at rest.
fn initial_state(layout: &Layout, p: &Params, s0: f64, v0: f64, gap: f64) -> Vec<f64> {
    let mut y0 = vec![0.0; layout.n.max(1)];
    let x_t0 = -s0;
    if let Some(i) = layout.tool {
        y0[i] = x_t0;
        y0[i + 1] = v0;
    }
    if let Some(j) = layout.object {
        y0[j] = x_t0 + gap;
        y0[j + 1] = 0.0;
    }
    if let Some(q) = layout.liquid {
        // at rest: the chamber at the gas pressure, the gas volume that of the lumped model
        y0[q] = physics::gas_pressure(p.p10, p.v_g0, p.a_p, p.kappa, s0);
        y0[q + 1] = p.a_p * s0;
    }
    y0
}

impl Regime {
    /// The regime at the preload equilibrium of stroke `s0`: on the forward stop when
    /// preloaded, the object stuck when plane friction can hold it, nothing else on.
    fn at_preload(p: &Params, s0: f64) -> Regime {
        Regime {
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
        }
    }
}

impl Model {
    /// Assemble a (validated) scene; the initial state is the static preload equilibrium.
    pub fn new(scene: &Scene) -> Model {
        let layout = Layout::of(scene);
        let p = Params::of(scene);
        let (robot, v0) = robot_at_start(scene);
        let s0 = p.preload_stroke();
        let y0 = initial_state(&layout, &p, s0, v0, scene.object.gap);
        let regime = Regime::at_preload(&p, s0);
        let (event_set, events, n_events) = p.event_functions();
        // with a compressible liquid the gas law is one of the volume moved through the orifice
        let gas_area = if layout.liquid.is_some() { 1.0 } else { p.a_p };
        let mut m = Model {
            gas: GasLaw::new(p.p10, p.v_g0, gas_area, p.kappa),
            p,
            layout,
            regime,
            step_regime: regime,
            robot,
            pending_brake: None,
            time_stop_was_kink: false,
            events,
            n_events,
            event_set,
            metrics: Metrics::default(),
            log: Vec::new(),
            t_end: scene.t_end,
            preload_stroke: s0,
            y0: Vec::new(),
        };
        m.start_stuck_if_friction_holds(&y0);
        m.step_regime = m.regime;
        m.y0 = y0;
        m
    }

    /// Dry friction: the tool starts stuck to the flange if static friction can hold it at
    /// `y0`, else slipping the way its holding force pushes it.
    fn start_stuck_if_friction_holds(&mut self, y0: &[f64]) {
        if self.p.d > 0.0 && self.p.module != Module::Rigid {
            self.regime.tool_stuck = true;
            let e = self.eval(0.0, y0, self.robot.current(), &self.regime);
            if e.f_f.abs() > self.p.d {
                self.regime.tool_stuck = false;
                self.regime.tool_dir = e.f_f.signum();
            }
        }
    }

    /// The regime in force during the step being reported to observers (`on_step`).
    pub(crate) fn step_regime(&self) -> &Regime {
        &self.step_regime
    }

    /// The tool moves with the robot (rigid module, or stuck by dry friction): the force on it
    /// jumps where the robot's acceleration does.
    pub(crate) fn tool_moves_with_robot(&self) -> bool {
        self.p.module == Module::Rigid || self.regime.tool_stuck
    }
}

/// The largest state a scene can need (tool 2 + liquid 2 + object 2 + ledger 3: work,
/// dissipation, the liquid's energy + contact impulse 1).
pub const MAX_STATES: usize = 10;
