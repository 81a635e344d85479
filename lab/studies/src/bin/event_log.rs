//! Print a scene's event log (time, name, stroke): `event_log SCENE.toml [KEY=VALUE]...`.
use cushion_model::{simulate, RunOptions};
use cushion_studies::{scene_from, set_key};

fn main() {
    let mut args = std::env::args().skip(1);
    let mut scene = scene_from(args.next().as_deref());
    for arg in args {
        assert!(set_key(&mut scene, &arg), "{arg}: not KEY=VALUE");
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
