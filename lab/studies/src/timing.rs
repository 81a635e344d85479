//! What the integrator's benchmarks (`oscillator`, `stiff_ode`) share.

use std::time::Instant;

/// Median wall time of `run` over repetitions adding up to about `budget` seconds (at least 3,
/// at most 10,000), and how many there were.
pub fn wall_time<R>(budget: f64, mut run: impl FnMut() -> R) -> (f64, usize) {
    let mut samples = Vec::new();
    let start = Instant::now();
    while samples.len() < 3 || (start.elapsed().as_secs_f64() < budget && samples.len() < 10_000) {
        let t = Instant::now();
        std::hint::black_box(run());
        samples.push(t.elapsed().as_secs_f64());
    }
    samples.sort_by(|a, b| a.total_cmp(b));
    (samples[samples.len() / 2], samples.len())
}
