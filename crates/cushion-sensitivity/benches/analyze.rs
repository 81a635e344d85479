//! The analysis of issue-sized studies alone, without the runs: D = 4 inputs, N = 2^14 base
//! points, second order (163,840 rows), 24 output columns, 1,000 bootstrap resamples.
//!
//!     cargo bench -p cushion-sensitivity --bench analyze [-- ROUNDS]
//!
//! The columns are smooth functions of the sample's unit points with interactions (an Ishigami
//! function per column, its coefficients varied), so every index is non-trivial. Prints the wall
//! time of each round and the fastest, on the global rayon pool (RAYON_NUM_THREADS sets it).

use std::time::Instant;

use cushion_sensitivity::{analyze, SaltelliSample, SobolOptions};

fn main() {
    let rounds: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(3);
    let (d, n, outputs) = (4, 1 << 14, 24);
    let sample = SaltelliSample::new(d, n, true, 0).expect("a valid sample");
    let rows = sample.n_rows() as usize;
    let mut unit = vec![0.0; d];
    let mut columns = vec![Vec::with_capacity(rows); outputs];
    for r in 0..rows {
        sample.fill_unit_point(r as u64, &mut unit);
        let x: Vec<f64> = unit
            .iter()
            .map(|u| std::f64::consts::PI * (2.0 * u - 1.0))
            .collect();
        for (o, c) in columns.iter_mut().enumerate() {
            let (a, b) = (1.0 + o as f64 * 0.5, 0.05 + 0.01 * o as f64);
            c.push(
                x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin() + 0.3 * x[3],
            );
        }
    }
    let refs: Vec<&[f64]> = columns.iter().map(|c| c.as_slice()).collect();
    let options = SobolOptions {
        second_order: true,
        resamples: 1000,
        conf_level: 0.95,
        seed: 0,
    };
    let mut best = f64::INFINITY;
    for round in 0..rounds {
        let started = Instant::now();
        let result = analyze(d, &refs, &options).expect("the analysis runs");
        let seconds = started.elapsed().as_secs_f64();
        best = best.min(seconds);
        let s1 = result[0]
            .indices()
            .map(|s| s.s1[1].value)
            .unwrap_or(f64::NAN);
        println!("round {round}: {seconds:.3} s (output 0: S1 of input 1 = {s1:.4})");
    }
    println!(
        "analysis of {outputs} outputs x {rows} rows, 1000 resamples, {} threads: fastest {best:.3} s",
        rayon::current_num_threads()
    );
}
