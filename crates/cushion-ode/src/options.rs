//! Solver settings: the method and everything that steers it.

use crate::system::MAX_EVENTS;
use crate::State;

/// The integration method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Adaptive Dormand–Prince 5(4) (Hairer's DOPRI5): FSAL, PI control, 4th-order dense output.
    Dp5,
    /// Adaptive Dormand–Prince 8(5,3) (Hairer's DOP853): order 8, 12 stages, PI control with
    /// the code's constants, 7th-order dense output (3 more stages per accepted step); for
    /// tight tolerances.
    Dop853,
    /// Adaptive Rosenbrock 4(3) (Hairer and Wanner's RODAS), L-stable, for stiff problems:
    /// Jacobian (the system's or by finite differences), predictive control, 3rd-order dense
    /// output.
    Rodas,
    /// DOPRI5 while the problem is not stiff, Rodas while it is, switching with hysteresis
    /// (`auto.rs`).
    Auto,
    /// Classical 4th-order Runge–Kutta with a fixed step `SolverOptions::fixed_step`.
    Rk4,
    /// Explicit Euler with a fixed step `SolverOptions::fixed_step`.
    Euler,
}

impl Method {
    /// The name users type (`dp5`, `dop853`, `rodas`, `auto`, `rk4`, `euler`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Dp5 => "dp5",
            Method::Dop853 => "dop853",
            Method::Rodas => "rodas",
            Method::Auto => "auto",
            Method::Rk4 => "rk4",
            Method::Euler => "euler",
        }
    }

    /// Every method's name, in the order users see them.
    pub const NAMES: [&'static str; 6] = ["dp5", "dop853", "rodas", "auto", "rk4", "euler"];

    /// Parse a user's name; `None` if unknown.
    pub fn from_name(s: &str) -> Option<Method> {
        match s {
            "dp5" => Some(Method::Dp5),
            "dop853" => Some(Method::Dop853),
            "rodas" => Some(Method::Rodas),
            "auto" => Some(Method::Auto),
            "rk4" => Some(Method::Rk4),
            "euler" => Some(Method::Euler),
            _ => None,
        }
    }

    /// Whether the step size adapts to an error estimate.
    pub fn is_adaptive(self) -> bool {
        matches!(
            self,
            Method::Dp5 | Method::Dop853 | Method::Rodas | Method::Auto
        )
    }
}

/// A tolerance: one number for every component, or one per component.
#[derive(Clone, Debug, PartialEq)]
pub enum Tolerance {
    Scalar(f64),
    PerComponent(Vec<f64>),
}

impl Tolerance {
    /// The tolerance of component `i`.
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Tolerance::Scalar(v) => *v,
            Tolerance::PerComponent(v) => v.get(i).copied().unwrap_or(f64::NAN),
        }
    }
}

impl From<f64> for Tolerance {
    fn from(v: f64) -> Self {
        Tolerance::Scalar(v)
    }
}

/// What Hairer's stiffness test does once it fires.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StiffnessAction {
    /// Do not test.
    Off,
    /// Record it in the statistics (with the time it started) and go on.
    Warn,
    /// Record it and stop with status `Stiff`.
    Stop,
}

/// Which points the solution records.
#[derive(Clone, Debug, PartialEq)]
pub enum Output {
    /// Only the final state.
    None,
    /// Every accepted step's end (and the start).
    Steps,
    /// These times (ascending), from the dense output; times outside `[t0, t_end]` are skipped.
    Times(Vec<f64>),
}

/// Every setting of a solve. `Default` gives Hairer's defaults with `rtol = 1e-6`, `atol = 1e-9`.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverOptions {
    pub method: Method,
    /// Relative tolerance.
    pub rtol: Tolerance,
    /// Absolute tolerance, in the units of each state component.
    pub atol: Tolerance,
    /// First step size; `None` chooses it by Hairer's initial step selection.
    pub h0: Option<f64>,
    /// Largest step size (default: the whole interval).
    pub h_max: f64,
    /// The step of the fixed-step methods (RK4, Euler).
    pub fixed_step: f64,
    /// Most steps (accepted and rejected) before giving up with `MaxSteps`.
    pub max_steps: u64,
    /// Safety factor of DOPRI5's PI step controller (Hairer: 0.9). The controller comes with
    /// the method: `Rodas` has RODAS's own (`controller::PredictiveController::rodas`),
    /// `Dop853` DOP853's (`controller::PiController::dop853`), and these four settings are
    /// DOPRI5's.
    pub safety: f64,
    /// PI controller's `beta` (Hairer: 0.04).
    pub beta: f64,
    /// Bounds of the step ratio `h_new / h` (Hairer: 0.2 and 10).
    pub min_ratio: f64,
    pub max_ratio: f64,
    /// Hairer's stiffness test (DOPRI5 and DOP853, each with 0.9 of its own stability
    /// boundary as threshold: the other methods report no estimate).
    pub stiffness: StiffnessAction,
    /// Times where `f` is not smooth: stepped onto exactly, never across.
    pub time_stops: Vec<f64>,
    /// Interior points of the dense output checked for sign changes of event functions in each
    /// step (besides its two ends), so that two crossings inside one step are both found.
    pub event_subdivisions: usize,
    /// Which points to record.
    pub output: Output,
    /// How many of the state's components are quadratures: integrals `q' = g(t, y)` of the
    /// others that no rate reads (a dissipated energy, a work, an impulse). They stay in the
    /// error norm, but its mean square is taken over the other components only: a quadrature
    /// adds its squared error without adding to the count. In the plain RMS, each quadrature
    /// whose error is small (a smooth integral) would lower the norm by adding to the count, and
    /// so widen the steps of the solution and worsen its accuracy by how many quadratures there
    /// are; here such a quadrature leaves the steps nearly as they are without it, while one
    /// whose integrand changes where the other components do not (a contact force growing while
    /// both bodies are held still) still limits the step. CVODES's `errconQ` chooses between
    /// leaving quadratures out of the norm and counting them as components; this is between the
    /// two. 0: none; at most `N - 1`.
    pub quadratures: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            method: Method::Dp5,
            rtol: Tolerance::Scalar(1e-6),
            atol: Tolerance::Scalar(1e-9),
            h0: None,
            h_max: f64::INFINITY,
            fixed_step: 1e-4,
            max_steps: 1_000_000,
            safety: 0.9,
            beta: 0.04,
            min_ratio: 0.2,
            max_ratio: 10.0,
            stiffness: StiffnessAction::Warn,
            time_stops: Vec::new(),
            event_subdivisions: 4,
            output: Output::None,
            quadratures: 0,
        }
    }
}

impl SolverOptions {
    /// Check the settings for a problem of `N` states and `n_events` event functions from
    /// `(t0, y0)` to `t_end`; `Err` holds the message of an `InvalidInput` status.
    pub fn check<const N: usize>(
        &self,
        t0: f64,
        y0: &State<N>,
        t_end: f64,
        n_events: usize,
    ) -> Result<(), String> {
        let opts = self;
        let tol_ok = |name: &str, tol: &Tolerance, allow_zero: bool| -> Result<(), String> {
            if let Tolerance::PerComponent(v) = tol {
                if v.len() != N {
                    return Err(format!(
                        "{name} has {} components, the state has {N}",
                        v.len()
                    ));
                }
            }
            for i in 0..N {
                let x = tol.get(i);
                let bad = !x.is_finite() || x < 0.0 || (!allow_zero && x == 0.0);
                if bad {
                    return Err(format!("{name}[{i}] = {x}: must be a finite number > 0"));
                }
            }
            Ok(())
        };
        tol_ok("rtol", &opts.rtol, true)?;
        tol_ok("atol", &opts.atol, true)?;
        if (0..N).any(|i| opts.rtol.get(i) == 0.0 && opts.atol.get(i) == 0.0) {
            return Err("rtol and atol are both zero for a component".into());
        }
        if !t0.is_finite() || !t_end.is_finite() || t_end < t0 {
            return Err(format!(
                "t0 = {t0}, t_end = {t_end}: need finite t0 <= t_end"
            ));
        }
        if !(opts.h_max > 0.0) {
            return Err(format!("h_max = {}: must be > 0", opts.h_max));
        }
        if let Some(h0) = opts.h0 {
            if !(h0 > 0.0 && h0.is_finite()) {
                return Err(format!("h0 = {h0}: must be a finite number > 0"));
            }
        }
        if !opts.method.is_adaptive() && !(opts.fixed_step > 0.0 && opts.fixed_step.is_finite()) {
            return Err(format!(
                "fixed_step = {}: must be a finite number > 0",
                opts.fixed_step
            ));
        }
        if n_events > MAX_EVENTS {
            return Err(format!("{n_events} event functions: at most {MAX_EVENTS}"));
        }
        if !(0.0 < opts.min_ratio
            && opts.min_ratio < 1.0
            && opts.max_ratio > 1.0
            && opts.safety > 0.0
            && opts.safety <= 1.0)
        {
            return Err("step controller settings out of range".into());
        }
        if opts.quadratures >= N {
            return Err(format!(
                "quadratures = {}: the state has {N} components, and the error norm needs at least one that is not a quadrature",
                opts.quadratures
            ));
        }
        if !y0.iter().all(|v| v.is_finite()) {
            return Err("the initial state is not finite".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_norm_needs_a_component_that_is_not_a_quadrature() {
        let y0 = State::<3>::zeros();
        let opts = |quadratures| SolverOptions {
            quadratures,
            ..SolverOptions::default()
        };
        assert!(opts(2).check(0.0, &y0, 1.0, 0).is_ok());
        let e = opts(3).check(0.0, &y0, 1.0, 0).unwrap_err();
        assert!(e.contains("quadratures = 3"), "{e}");
    }
}
