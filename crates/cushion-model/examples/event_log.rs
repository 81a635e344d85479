//! Print a scene's event log (time, name, stroke): `event_log SCENE.toml [KEY=VALUE]...`.
use cushion_model::{simulate, RunOptions, Scene};
fn main() {
    let mut args = std::env::args().skip(1);
    let mut scene = match args.next() {
        Some(path) => Scene::from_file(std::path::Path::new(&path)).expect("readable scene"),
        None => Scene::default(),
    };
    for arg in args {
        let (k, v) = arg.split_once('=').expect("KEY=VALUE");
        scene.set_from_str(k, v).expect("valid");
    }
    let r = simulate(&scene, &RunOptions::default());
    for e in &r.events {
        println!(
            "{:>12.6} ms  {:<22} s = {:.6} mm",
            e.t * 1e3,
            e.name,
            e.point.s * 1e3
        );
    }
    println!("{:?}", r.summary.stats);
}
