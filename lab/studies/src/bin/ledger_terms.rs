//! The energy ledger's terms at the end of a run: `ledger_terms SCENE.toml [KEY=VALUE]...`.
use cushion_model::{simulate_with_ledger, RunOptions};
use cushion_studies::{scene_from, set_key};

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("ledger_terms SCENE.toml [KEY=VALUE]...");
    let mut scene = scene_from(Some(&path));
    for arg in args {
        assert!(set_key(&mut scene, &arg), "{arg}: not KEY=VALUE");
    }
    let (r, ledger) = simulate_with_ledger(&scene, &RunOptions::default());
    println!(
        "status {:?}, energy_residual {:?}",
        r.summary.status, r.summary.energy_residual
    );
    match ledger {
        Some(l) => println!("{l:#?}"),
        None => println!("no ledger"),
    }
}
