//! The integrator alone on a smooth problem with a closed form (a benchmark, not a test): the
//! damped linear oscillator `x'' + 2 zeta w x' + w^2 x = 0`, `x(0) = 1`, `x'(0) = 0`, to `T`,
//! as `lab/work_precision.py` gives it to every peer.
//!
//! `oscillator W ZETA T METHOD=SETTING...` with `dp5=1e-6` (rtol; atol = rtol / 1000), `rk4=h1e-4`
//! (a fixed step), one line per setting: `method setting status x'(T) seconds evaluations
//! repeats`, `seconds` the median wall time of the repeated solves (about 0.2 s of them, at
//! least 3), with no
//! events, no observers and the final state only: what the integrator costs on its own.

use cushion_studies::timing::wall_time;

use cushion_ode::{solve, Matrix, Method, OdeSystem, Solution, SolverOptions, State, Tolerance};

struct Oscillator {
    w: f64,
    zeta: f64,
}

impl OdeSystem<2> for Oscillator {
    fn rhs(&self, _t: f64, y: &State<2>) -> State<2> {
        State::<2>::new(
            y[1],
            -2.0 * self.zeta * self.w * y[1] - self.w * self.w * y[0],
        )
    }
    fn jacobian(&self, _t: f64, _y: &State<2>) -> Option<Matrix<2>> {
        Some(Matrix::<2>::new(
            0.0,
            1.0,
            -self.w * self.w,
            -2.0 * self.zeta * self.w,
        ))
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "oscillator W ZETA T METHOD=SETTING... (dp5=1e-6: rtol; rk4=h1e-4: fixed step)";
    let number = |i: usize| -> f64 {
        args.get(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or_else(|| panic!("{usage}"))
    };
    let (w, zeta, t_end) = (number(0), number(1), number(2));
    for arg in &args[3..] {
        let (name, setting) = arg.split_once('=').unwrap_or_else(|| panic!("{usage}"));
        let method = Method::from_name(name).unwrap_or_else(|| panic!("unknown method {name}"));
        let mut opts = SolverOptions {
            method,
            ..Default::default()
        };
        match setting.strip_prefix('h') {
            Some(h) => opts.fixed_step = h.parse().unwrap_or_else(|_| panic!("{usage}")),
            None => {
                let rtol: f64 = setting.parse().unwrap_or_else(|_| panic!("{usage}"));
                opts.rtol = Tolerance::Scalar(rtol);
                opts.atol = Tolerance::Scalar(rtol / 1000.0);
            }
        }
        let run = || -> Solution<2> {
            solve(
                &mut Oscillator { w, zeta },
                0.0,
                State::<2>::new(1.0, 0.0),
                t_end,
                &opts,
            )
        };
        let sol = run();
        let (seconds, repeats) = wall_time(0.2, run);
        println!(
            "{name} {setting} {:?} {:.17e} {seconds:.6e} {} {repeats}",
            sol.status, sol.y[1], sol.stats.rhs_evals
        );
    }
}
