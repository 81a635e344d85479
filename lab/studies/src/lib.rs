//! The lab's study binaries (`src/bin/`, one per study, run by the scripts in `lab/`; see
//! `lab/README.md`) and what they share: here a seeded generator, issue 4's design axes and a
//! scene from its file and `KEY=VALUE` arguments; the wide random scenes in [`wide`], a median
//! wall time in [`timing`]. Not published: a benchmark or a study, not part of the engine.

use cushion_model::Scene;

/// xorshift64 numbers, uniform in [0, 1): the same seed gives the same scenes.
pub struct Uniform(u64);

impl Uniform {
    pub fn new(seed: u64) -> Self {
        Uniform(seed)
    }

    /// The next number, uniform in [0, 1). A draw that never ends (an `f64`, never `None`): not
    /// an `Iterator`, which Clippy asks of a public `next`.
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, lo + width)`.
    pub fn span(&mut self, lo: f64, width: f64) -> f64 {
        lo + width * self.next()
    }

    /// Log-uniform in `[lo, hi)`.
    pub fn log_between(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.next()).exp()
    }
}

/// Gas pressure 300 Pa-100 kPa (log), orifice radius 2-12 mm, object mass 0.05-1 kg, drawn in
/// this order (the dead time, 0-0.1 s, is drawn first by the caller).
pub fn draw_module_axes(s: &mut Scene, u: &mut Uniform) {
    s.hydraulic.gas_pressure = u.log_between(300.0, 1e5);
    s.hydraulic.orifice_radius = u.span(0.002, 0.010);
    s.object.mass = u.span(0.05, 0.95);
}

/// The scene in the file at `path`, or the defaults without one.
pub fn scene_from(path: Option<&str>) -> Scene {
    path.map_or_else(Scene::default, |p| {
        Scene::from_file(std::path::Path::new(p)).unwrap_or_else(|e| panic!("{p}: {e}"))
    })
}

/// Set the key of a `KEY=VALUE` argument in `scene`; `false` (and `scene` unchanged) when the
/// argument has no `=`.
pub fn set_key(scene: &mut Scene, arg: &str) -> bool {
    match arg.split_once('=') {
        Some((k, v)) => {
            scene
                .set_from_str(k, v)
                .unwrap_or_else(|e| panic!("{arg}: {e}"));
            true
        }
        None => false,
    }
}

pub mod timing;
pub mod wide;
