//! The peaks of a run: the largest `|F_r|` (reported signed, with its time), the largest
//! contact force `F_c`, the largest stroke, and the compressible liquid's largest gas pressure.
//! [`PeakSampler`] is the one entry point: an observer of the run (`observe.rs`) that samples
//! every accepted step and hands the early end the peaks so far ([`Peaks`]).
//!
//! Peaks are found as the samples come: each quantity is sampled at every step's end and at
//! three points inside where a new peak is possible (`sampler.rs`), and every local top of its
//! samples that comes near the largest value so far (`tracker.rs`) is located at once, by
//! Brent's search on the dense output around it (`search.rs`): the two sample intervals on
//! either side of the top sample.
//!
//! That is one rule for every case. A top inside a step is searched on that step's own dense
//! output, exact for any method. A top at a step's end is confirmed only by the next step's
//! first sample, and the peak may lie on either side of it: the step before is then kept (its
//! dense output, `kept_step.rs`) and both sides are searched
//! (`tests/model/peaks.rs::peaks_just_after_a_step_end_are_found`). Several tops of nearly the same
//! height (a bistable module's back-stop impact and a later one, 0.04 % apart; one peak with
//! two tops and a shallow dip) are each searched, so the one with the larger sample need not
//! hold the larger peak. Where a quantity jumps (`F_r` at a robot kink under a rigid tool) the
//! value after the jump is exact where it is, and is offered as found (`PeakTracker::found`).
//! Where a step's dense output is not stable (DOP853 at its stability boundary), a force's top
//! is searched on the step integrated again in halves (`top_step.rs`).
//!
//! Files: `sampler.rs` the observer (what is sampled where), `tracker.rs` one quantity's peak
//! as its samples arrive, `search.rs` Brent's search of a top, `kept_step.rs` the step kept
//! while its end may be a top, `top_step.rs` the step integrated again in halves.

mod kept_step;
mod sampler;
mod search;
mod top_step;
mod tracker;

pub(crate) use sampler::{PeakSampler, Peaks};

#[cfg(test)]
mod tests;
