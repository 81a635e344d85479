"""SciPy's stiff solvers on the problems of `crates/cushion-ode/tests/integrator/rodas_stiff.rs`, with the
same tolerances and analytic Jacobians, for comparison with the engine's (`python -m lab.stiff_ode` runs both):
evaluations of f (nfev; none spent on Jacobians), Jacobians (njev), LU factorizations (nlu),
the mixed error at the end against the same reference, and wall time.

    bash lab/setup_venv.sh && .venv/bin/python -m lab.stiff_scipy
"""
import time

import numpy as np
from scipy.integrate import solve_ivp


def vdp(mu):
    def f(t, y):
        return [y[1], mu * ((1 - y[0] ** 2) * y[1] - y[0])]

    def jac(t, y):
        return [[0.0, 1.0], [mu * (-2 * y[0] * y[1] - 1), mu * (1 - y[0] ** 2)]]

    return f, jac


def rober_f(t, y):
    r1, r2, r3 = 0.04 * y[0], 1e4 * y[1] * y[2], 3e7 * y[1] ** 2
    return [-r1 + r2, r1 - r2 - r3, r3]


def rober_jac(t, y):
    return [
        [-0.04, 1e4 * y[2], 1e4 * y[1]],
        [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
        [0.0, 6e7 * y[1], 0.0],
    ]


def hires_f(t, y):
    r = 280 * y[5] * y[7]
    return [
        -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
        1.71 * y[0] - 8.75 * y[1],
        -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4],
        8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3],
        -1.745 * y[4] + 0.43 * y[5] + 0.43 * y[6],
        -r + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6],
        r - 1.81 * y[6],
        -r + 1.81 * y[6],
    ]


def hires_jac(t, y):
    j = np.zeros((8, 8))
    j[0, :3] = [-1.71, 0.43, 8.32]
    j[1, :2] = [1.71, -8.75]
    j[2, 2:5] = [-10.03, 0.43, 0.035]
    j[3, 1:4] = [8.32, 1.71, -1.12]
    j[4, 4:7] = [-1.745, 0.43, 0.43]
    j[5, 3:8] = [0.69, 1.71, -0.43 - 280 * y[7], 0.69, -280 * y[5]]
    j[6, 5:8] = [280 * y[7], -1.81, 280 * y[5]]
    j[7, 5:8] = [-280 * y[7], 1.81, -280 * y[5]]
    return j


S, W, Q = 77.27, 0.161, 8.375e-6


def orego_f(t, y):
    return [S * (y[1] + y[0] * (1 - Q * y[0] - y[1])), (y[2] - (1 + y[0]) * y[1]) / S, W * (y[0] - y[2])]


def orego_jac(t, y):
    return [
        [S * (1 - 2 * Q * y[0] - y[1]), S * (1 - y[0]), 0.0],
        [-y[1] / S, -(1 + y[0]) / S, 1 / S],
        [W, 0.0, -W],
    ]


def rows():
    """Radau and BDF on each problem: one dict per run."""
    vdp6, vdp6j = vdp(1e6)
    vdp3, vdp3j = vdp(1e3)
    ref_vdp3 = solve_ivp(vdp3, (0, 2), [2.0, -0.66], method="Radau", jac=vdp3j, rtol=1e-12, atol=1e-12).y[:, -1]
    problems = [
        ("VDPOL mu=1e6", vdp6, vdp6j, [2.0, 0.0], 2.0, 1e-6, [1e-6] * 2,
         [0.1706167732170483e1, -0.8928097010247975]),
        ("VDPOL mu=1e3", vdp3, vdp3j, [2.0, -0.66], 2.0, 1e-6, [1e-6] * 2, ref_vdp3),
        ("ROBER", rober_f, rober_jac, [1.0, 0.0, 0.0], 1e11, 1e-6, [1e-10, 1e-16, 1e-10],
         [0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050]),
        ("HIRES", hires_f, hires_jac, [1, 0, 0, 0, 0, 0, 0, 0.0057], 321.8122, 1e-6, [1e-10] * 8,
         [0.7371312573325668e-3, 0.1442485726316185e-3, 0.5888729740967575e-4,
          0.1175651343283149e-2, 0.2386356198831331e-2, 0.6238968252742796e-2,
          0.2849998395185769e-2, 0.2850001604814231e-2]),
        ("OREGO", orego_f, orego_jac, [1.0, 2.0, 3.0], 360.0, 1e-6, [1e-8] * 3,
         [0.1000814870318523e1, 0.1228178521549917e4, 0.1320554942846706e3]),
    ]
    out = []
    for name, f, jac, y0, t_end, rtol, atol, ref in problems:
        for method in ["Radau", "BDF"]:
            t = time.perf_counter()
            sol = solve_ivp(f, (0, t_end), y0, method=method, jac=jac, rtol=rtol, atol=atol)
            wall = time.perf_counter() - t
            y = sol.y[:, -1]
            err = max(abs(y[i] - ref[i]) / (atol[i] + rtol * abs(ref[i])) for i in range(len(y)))
            out.append({"problem": name, "method": f"SciPy {method}", "steps": len(sol.t) - 1, "rhs_evals": int(sol.nfev),
                        "jacobians": int(sol.njev), "lus": int(sol.nlu), "mixed_error": float(err),
                        "wall_ms": 1e3 * wall})
    return out


def main():
    print(f"{'problem':14} {'method':12} {'steps':>6} {'nfev':>7} {'njev':>6} {'nlu':>6} {'mixed err':>9} {'wall ms':>8}")
    for r in rows():
        print(f"{r['problem']:14} {r['method']:12} {r['steps']:6d} {r['rhs_evals']:7d} {r['jacobians']:6d} "
              f"{r['lus']:6d} {r['mixed_error']:9.2f} {r['wall_ms']:8.1f}")


if __name__ == "__main__":
    main()
