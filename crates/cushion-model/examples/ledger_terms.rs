//! The energy ledger's terms at the end of a run: `ledger_terms SCENE.toml [KEY=VALUE]...`.
use cushion_model::{simulate_with_ledger, RunOptions, Scene};
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("ledger_terms SCENE.toml [KEY=VALUE]...");
    let mut scene = Scene::from_file(std::path::Path::new(&path)).expect("readable scene");
    for arg in args {
        let (k, v) = arg.split_once('=').expect("KEY=VALUE");
        scene.set_from_str(k, v).expect("valid");
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
