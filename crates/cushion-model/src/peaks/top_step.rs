//! A step that holds a top, integrated again in two halves whose dense outputs can be trusted
//! with it, where the method's own cannot: DOP853's.
//!
//! An explicit method on a stiff stretch (a strong orifice damping the tool against the robot
//! force) steps at its stability boundary, and its dense output there is not stable. For
//! `y' = lambda y` with `z = h lambda`, DOP853's continuous extension at mid-step is
//! `P(1/2, z) = 0.77` at `z = -5` and `8.1` at `z = -6`, where the step's own factor is
//! `R(z) = -0.06` and `-0.49`: a fast mode's small deviation, which the error test holds at the
//! tolerance at the step's ends, is amplified ten times or more inside the step. DOPRI5's
//! extension stays within its `R(z)` up to its boundary (`P(1/2, -3) = -0.22`, `R(-3) = 0.57`).
//! On the design space at rtol 1e-6, DOP853's dense output put the peak robot force up to
//! 1.2e-3 (relative) off, through the tool's velocity under the orifice's `v |v|`, and its
//! tops tens of microseconds away from the true ones.
//!
//! Half the step halves `z`: at `z = -3` the extension is within 1 % of the exact factor
//! (`P(1/2, -3) = 0.2256`, `exp(-1.5) = 0.2231`). So under DOP853 a force's top in such a step
//! is searched on the dense outputs of two DOP853 steps over the halves of the step, from its
//! start, each as accurate as the accepted step
//! (`tests/model/peaks.rs::dop853_tops_are_searched_on_half_steps`; which quantities:
//! `sampler.rs`, `FAST`). They cost [`EVALS`] evaluations of `f` a step, counted with the
//! run's. DOP853 is the one method whose dense output has a finite stability boundary
//! (`cushion_ode::stepper::Stepper::dense_stability_boundary`), so a step whose dense output is
//! not stable is a DOP853 step, and the halves are DOP853's too.

use super::kept_step::{KeptStep, MAX_DYNAMIC};
use super::search::locate_on;
use super::tracker::{Bracket, Peak};
use crate::model::{Eval, Model, Regime};
use crate::physics::Segment;
use cushion_ode::dop853::Dop853;
use cushion_ode::stepper::Stepper;
use cushion_ode::{OdeSystem, State};

/// Evaluations of `f` the two halves take: 12 stages each, `f` at the end and the three stages
/// of the continuous extension, the second half's first stage being the first's end.
pub(crate) const EVALS: u64 = 31;

/// The physics in the segment and the regime one step ran in, over the states it reads (the
/// quadratures after them, integrated from zero, enter no force).
struct InStep<'a> {
    model: &'a Model,
    seg: &'a Segment,
    regime: &'a Regime,
}

impl OdeSystem<MAX_DYNAMIC> for InStep<'_> {
    #[inline]
    fn rhs(&self, t: f64, y: &State<MAX_DYNAMIC>) -> State<MAX_DYNAMIC> {
        self.model.rates(t, y, self.seg, self.regime)
    }
}

/// A step integrated again in two halves.
pub(crate) struct Halves {
    halves: [KeptStep; 2],
}

impl Halves {
    /// The step `step` (its dense output gives the start and the span), integrated again in two
    /// DOP853 steps; `None` if a stage is not finite (the caller keeps the step's own dense
    /// output).
    pub fn of(model: &Model, step: &KeptStep) -> Option<Halves> {
        let sys = InStep {
            model,
            seg: &step.seg,
            regime: &step.regime,
        };
        let (t0, h) = (step.dense.t0, 0.5 * step.dense.h);
        let mut method = Dop853::<MAX_DYNAMIC>::new();
        let mut half = |t: f64, y: &State<MAX_DYNAMIC>, f: &State<MAX_DYNAMIC>| {
            let mut a = method.step(&sys, t, y, f, h).ok()?;
            method.complete(&sys, t, y, h, &mut a);
            let dense = method.dense(t, h, y, f, &a);
            let f1 = a.f1?;
            let finite = a.y1.iter().chain(f1.iter()).all(|v| v.is_finite());
            finite.then_some((
                KeptStep {
                    dense,
                    seg: step.seg,
                    regime: step.regime,
                    dense_stable: true,
                },
                a.y1,
                f1,
            ))
        };
        let y0 = step.start();
        let f0 = sys.rhs(t0, &y0);
        let (first, y_mid, f_mid) = half(t0, &y0, &f0)?;
        let (second, _, _) = half(t0 + h, &y_mid, &f_mid)?;
        Some(Halves {
            halves: [first, second],
        })
    }

    /// The physics at `t` on the half that holds it.
    pub fn eval(&self, model: &Model, t: f64) -> Eval {
        let [first, second] = &self.halves;
        if t < second.dense.t0 {
            first.eval(model, t)
        } else {
            second.eval(model, t)
        }
    }
}

/// The steps around a top whose dense output is not stable: the current step and the kept one
/// before it, each integrated again in halves once a top first needs it.
pub(crate) struct Unstable<'a> {
    model: &'a Model,
    /// The current step, where its dense output is not stable.
    here: Option<KeptStep>,
    /// The kept step before it, where its dense output is not stable.
    kept: Option<&'a KeptStep>,
    here_halves: Option<Option<Halves>>,
    kept_halves: Option<Option<Halves>>,
    /// The evaluations of `f` the halves took.
    pub evals: u64,
}

impl<'a> Unstable<'a> {
    pub fn new(model: &'a Model, here: Option<KeptStep>, kept: Option<&'a KeptStep>) -> Self {
        Unstable {
            model,
            here,
            kept,
            here_halves: None,
            kept_halves: None,
            evals: 0,
        }
    }

    /// Locate the top of `value` in the bracket `b`, which reaches into an unstable step: on
    /// the halves of each unstable step, on `here_dense` and `behind_dense` (the steps' own
    /// dense outputs) elsewhere. The samples that chose the bracket came from the unstable
    /// dense output, which may put a top tens of microseconds from the true one: the whole of
    /// each unstable step the bracket touches is searched, from its sample's value taken
    /// again (`t0, t1`: the current step's span).
    #[cold]
    #[inline(never)]
    pub fn locate(
        &mut self,
        b: Bracket,
        (t0, t1): (f64, f64),
        value: impl Fn(&Eval) -> (f64, f64),
        here_dense: impl Fn(f64) -> Eval,
        behind_dense: impl Fn(f64) -> Eval,
    ) -> Peak {
        let model = self.model;
        let kept_touched = b.lo < t0 && self.kept.is_some();
        if let (Some(c), None) = (&self.here, &self.here_halves) {
            self.evals += EVALS;
            self.here_halves = Some(Halves::of(model, c));
        }
        if let (true, Some(c), None) = (kept_touched, self.kept, &self.kept_halves) {
            self.evals += EVALS;
            self.kept_halves = Some(Halves::of(model, c));
        }
        let here = |t: f64| match &self.here_halves {
            Some(Some(h)) => h.eval(model, t),
            _ => here_dense(t),
        };
        let behind = |t: f64| match &self.kept_halves {
            Some(Some(h)) if kept_touched => h.eval(model, t),
            _ => behind_dense(t),
        };
        let lo = match self.kept {
            Some(c) if kept_touched => c.dense.t0,
            _ if self.here.is_some() && b.lo >= t0 => t0,
            _ => b.lo,
        };
        let hi = if self.here.is_some() { t1 } else { b.hi };
        let v = if b.lo < t0 && b.t <= t0 {
            value(&behind(b.t)).0
        } else {
            value(&here(b.t)).0
        };
        let b = Bracket { lo, v, hi, ..b };
        locate_on(b, t0, value, here, behind)
    }
}
