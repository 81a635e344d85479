//! The recorded trajectory: the points [`Output`] asks for, as the steps pass them.

use crate::dense::DenseOutput;
use crate::options::Output;
use crate::State;

/// The points recorded so far.
pub(crate) struct Recorder<const N: usize> {
    pub(crate) ts: Vec<f64>,
    pub(crate) ys: Vec<State<N>>,
    /// The first of `Output::Times` not yet passed.
    next_output: usize,
}

impl<const N: usize> Recorder<N> {
    pub(crate) fn new() -> Self {
        Recorder {
            ts: Vec::new(),
            ys: Vec::new(),
            next_output: 0,
        }
    }

    /// The run's start `(t0, y0)`: recorded for `Output::Steps`, and if asked for.
    pub(crate) fn start(&mut self, output: &Output, t0: f64, y0: &State<N>) {
        if let Output::Steps = output {
            self.ts.push(t0);
            self.ys.push(*y0);
        } else {
            self.record(output, t0, None, t0, y0);
        }
    }

    /// Record the points `output` asks for in `[t0, t1]` not yet recorded, after a step from
    /// `t0` that ended at `(t1, y1)` (before any handler changed it), with its dense output.
    #[inline]
    pub(crate) fn record(
        &mut self,
        output: &Output,
        t0: f64,
        dense: Option<&DenseOutput<N>>,
        t1: f64,
        y1: &State<N>,
    ) {
        match output {
            Output::None => {}
            Output::Steps => {
                self.ts.push(t1);
                self.ys.push(*y1);
            }
            Output::Times(times) => {
                while self.next_output < times.len() && times[self.next_output] <= t1 {
                    let tr = times[self.next_output];
                    if tr >= t0 {
                        let yr = if tr == t1 {
                            *y1
                        } else {
                            match dense {
                                Some(d) => d.eval(tr),
                                None => *y1,
                            }
                        };
                        self.ts.push(tr);
                        self.ys.push(yr);
                    }
                    self.next_output += 1;
                }
            }
        }
    }
}
