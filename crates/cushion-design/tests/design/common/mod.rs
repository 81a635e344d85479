//! Drivers shared by the tests: a model is a closure of one run (design point, `for_all`
//! point, both in real units) giving its row of metric values. The drivers play the engine's
//! part: they evaluate each batch in an order and in chunks of their choosing, put the rows
//! back in the batch's order, and check that no run is asked for twice.
#![allow(dead_code)]

use std::collections::HashSet;

use cushion_design::{Refinement, Run, WorstCaseSearch};

/// A model: a run's design point and `for_all` point to its row of metric values.
pub type Model<'a> = dyn Fn(&[f64], &[f64]) -> Vec<f64> + 'a;

/// How the stand-in engine goes through a batch.
#[derive(Clone, Copy, Debug)]
pub enum Order {
    InOrder,
    /// Chunks of this many runs, the last chunk first and each chunk backwards.
    ReversedChunks(usize),
}

/// Evaluate a batch as `order` says and return the rows in the batch's order.
pub fn evaluate(batch: &[Run], model: &Model<'_>, order: Order) -> Vec<Vec<f64>> {
    let mut rows: Vec<Option<Vec<f64>>> = vec![None; batch.len()];
    let chunk = match order {
        Order::InOrder => batch.len().max(1),
        Order::ReversedChunks(k) => k.max(1),
    };
    let mut chunks: Vec<(usize, &[Run])> = batch
        .chunks(chunk)
        .enumerate()
        .map(|(i, c)| (i * chunk, c))
        .collect();
    if matches!(order, Order::ReversedChunks(_)) {
        chunks.reverse();
    }
    for (start, runs) in chunks {
        let mut idx: Vec<usize> = (0..runs.len()).collect();
        if matches!(order, Order::ReversedChunks(_)) {
            idx.reverse();
        }
        for i in idx {
            rows[start + i] = Some(model(&runs[i].design, &runs[i].for_all));
        }
    }
    rows.into_iter()
        .map(|r| r.expect("every run evaluated"))
        .collect()
}

/// The bits of a run, to find repeats.
fn run_key(r: &Run) -> Vec<u64> {
    r.design
        .iter()
        .chain(&r.for_all)
        .map(|x| x.to_bits())
        .collect()
}

/// Drive a worst-case search to its end; returns every batch it asked for.
pub fn drive_search(
    search: &mut WorstCaseSearch,
    model: &Model<'_>,
    order: Order,
) -> Vec<Vec<Run>> {
    let mut seen = HashSet::new();
    let mut batches = Vec::new();
    loop {
        let batch = search.ask();
        if batch.is_empty() {
            return batches;
        }
        for r in &batch {
            assert!(seen.insert(run_key(r)), "run asked for twice: {r:?}");
        }
        search
            .tell(evaluate(&batch, model, order))
            .expect("rows of the batch");
        batches.push(batch);
    }
}

/// Drive a refinement to its end; returns the number of runs made and of batches.
pub fn drive_refinement(map: &mut Refinement, model: &Model<'_>, order: Order) -> (usize, usize) {
    let mut seen = HashSet::new();
    let (mut runs, mut batches) = (0, 0);
    loop {
        let batch = map.ask();
        if batch.is_empty() {
            return (runs, batches);
        }
        for r in &batch {
            assert!(seen.insert(run_key(r)), "run asked for twice: {r:?}");
        }
        runs += batch.len();
        batches += 1;
        map.tell(evaluate(&batch, model, order))
            .expect("rows of the batch");
    }
}
