//! The Jacobian against central differences at random states in every regime.

use super::*;
use crate::config::Scene;

/// A small deterministic generator (no dependency for one test).
struct Lcg(u64);

impl Lcg {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn scene(sets: &[(&str, &str)]) -> Scene {
    let mut s = Scene::default();
    for (k, v) in sets {
        s.set_from_str(k, v).unwrap();
    }
    s
}

/// `df/dy` and `df/dt` by central differences, with steps small against each
/// variable's scale.
fn central<const N: usize>(
    m: &Model,
    t: f64,
    y: &State<N>,
    scale: &[f64],
) -> (Matrix<N>, State<N>) {
    let f = |t: f64, y: &State<N>| cushion_ode::OdeSystem::<N>::rhs(m, t, y);
    let mut jac = Matrix::<N>::zeros();
    for c in 0..N {
        let h = 1e-6 * scale[c];
        let (mut a, mut b) = (*y, *y);
        a[c] += h;
        b[c] -= h;
        jac.set_column(c, &((f(t, &a) - f(t, &b)) / (a[c] - b[c])));
    }
    let h = 1e-9;
    (jac, (f(t + h, y) - f(t - h, y)) / (2.0 * h))
}

fn check<const N: usize>(name: &str, m: &Model, t: f64, y: &State<N>, scale: &[f64]) {
    let (jac, dfdt) = m.jacobians(t, y, &m.regime);
    let (fd, fd_t) = central(m, t, y, scale);
    for k in 0..N {
        // compare each row in the units of its columns' scales
        let row_max = (0..N)
            .map(|c| fd[(k, c)].abs() * scale[c])
            .fold(fd_t[k].abs() * 1e-3, f64::max);
        for c in 0..N {
            let (a, b) = (jac[(k, c)] * scale[c], fd[(k, c)] * scale[c]);
            assert!(
                (a - b).abs() <= 1e-5 * b.abs() + 1e-7 * row_max,
                "{name}: d f{k} / d y{c}: analytic {} finite differences {} ({:?})",
                jac[(k, c)],
                fd[(k, c)],
                m.regime
            );
        }
        let (a, b) = (dfdt[k] * 1e-3, fd_t[k] * 1e-3);
        assert!(
            (a - b).abs() <= 1e-5 * b.abs() + 1e-7 * row_max,
            "{name}: d f{k} / dt: analytic {} finite differences {} ({:?})",
            dfdt[k],
            fd_t[k],
            m.regime
        );
    }
}

/// Random states in regime `regime` of the scene: each contact the regime has closed
/// penetrates (0.01 to 0.5 mm), speeds up to 1 m/s, the liquid's pressure about the
/// gas's.
fn states<const N: usize>(m: &Model, rng: &mut Lcg, t: f64) -> (State<N>, Vec<f64>) {
    let l = m.layout;
    let r = m.regime;
    let (x_r, _, _) = m.robot.current().at(t);
    let mut y = State::<N>::zeros();
    let mut scale = vec![1.0; N];
    let mut x_t = x_r;
    if let Some(i) = l.tool {
        let s = if r.fwd {
            -rng.uniform(1e-5, 5e-4)
        } else if r.back {
            m.p.stroke + rng.uniform(1e-5, 5e-4)
        } else {
            rng.uniform(1e-3, m.p.stroke - 1e-3)
        };
        x_t = x_r - s;
        y[i] = x_t;
        y[i + 1] = rng.uniform(-1.0, 1.0);
        scale[i] = 1e-3;
    }
    if let Some(q) = l.liquid {
        let s = x_r - x_t;
        y[q + 1] = m.p.a_p * s + rng.uniform(-1e-7, 1e-7);
        y[q] = m.gas.exact(y[q + 1]) + rng.uniform(-500.0, 500.0);
        scale[q] = 1e2;
        scale[q + 1] = 1e-8;
    }
    if let Some(j) = l.object {
        let d = if r.obj_contact {
            rng.uniform(1e-5, 5e-4)
        } else {
            -rng.uniform(1e-4, 1e-3)
        };
        y[j] = x_t - d;
        y[j + 1] = rng.uniform(-1.0, 1.0);
        scale[j] = 1e-3;
    }
    (y, scale)
}

#[test]
fn the_jacobian_matches_finite_differences_in_every_regime() {
    let ledger = ("energy.ledger", "true");
    let scenes: [(&str, Vec<(&str, &str)>); 6] = [
        ("hydraulic", vec![ledger]),
        (
            "compressible",
            vec![ledger, ("hydraulic.bulk_modulus", "1.5e9")],
        ),
        ("bistable", vec![ledger, ("module", "bistable")]),
        ("rigid", vec![ledger, ("module", "rigid")]),
        (
            "frictions",
            vec![
                ledger,
                ("tool.dry_friction", "0.5"),
                ("object.plane_friction", "0.3"),
            ],
        ),
        ("cavitation", vec![ledger, ("hydraulic.cavitation", "true")]),
    ];
    let mut rng = Lcg(7);
    let mut checked = 0;
    for (name, sets) in scenes {
        let mut m = Model::new(&scene(&sets));
        let n = m.layout.n;
        for bits in 0..256u32 {
            let bit = |k: u32| bits & (1 << k) != 0;
            let r = Regime {
                fwd: bit(0),
                back: bit(1) && !bit(0),
                obj_contact: bit(2),
                stop_released: bit(3),
                obj_released: bit(4),
                tool_stuck: bit(5) && m.p.d > 0.0,
                tool_dir: if bit(6) { 1.0 } else { -1.0 },
                obj_stuck: bit(7) && m.p.mu_n > 0.0,
                cavitating: bit(3) && m.p.p_cav.is_some(),
                ..m.regime
            };
            if (!m.layout.object.is_some() && bit(2))
                || (m.p.module == Module::Rigid && bits & 0b1011 != 0)
            {
                continue;
            }
            m.regime = r;
            for _ in 0..3 {
                let t = rng.uniform(0.0, 0.05);
                macro_rules! at {
                    ($n:literal) => {{
                        let (y, scale) = states::<$n>(&m, &mut rng, t);
                        check(name, &m, t, &y, &scale);
                    }};
                }
                match n {
                    4 => at!(4),
                    5 => at!(5),
                    6 => at!(6),
                    7 => at!(7),
                    8 => at!(8),
                    9 => at!(9),
                    10 => at!(10),
                    _ => panic!("{name}: {n} states"),
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}
