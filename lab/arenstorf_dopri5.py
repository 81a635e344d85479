"""Hairer's DOPRI5 (Fortran, through scipy.integrate.ode('dopri5')) on the Arenstorf orbit.

Prints right-hand-side evaluations and the end error for rtol = atol = 1e-4 .. 1e-10, to set
beside `cargo bench -p cushion-ode --bench step_cost`. Run: `.venv/bin/python -m lab.arenstorf_dopri5`
(`bash lab/setup_venv.sh` makes the virtual environment with numpy and scipy).
"""
import time

import numpy as np
from scipy.integrate import ode

MU = 0.012277471
MUP = 1.0 - MU
PERIOD = 17.0652165601579625588917206249
Y0 = np.array([0.994, 0.0, 0.0, -2.001585106379082522420537862224])


def main():
    print(f"{'tol':>8} {'rhs_evals':>10} {'end_error':>12} {'ms/solve':>10}")
    for k in range(4, 11):
        tol = 10.0 ** -k
        calls = [0]

        def f(t, y):
            calls[0] += 1
            d1 = ((y[0] + MU) ** 2 + y[1] ** 2) ** 1.5
            d2 = ((y[0] - MUP) ** 2 + y[1] ** 2) ** 1.5
            return [
                y[2],
                y[3],
                y[0] + 2 * y[3] - MUP * (y[0] + MU) / d1 - MU * (y[0] - MUP) / d2,
                y[1] - 2 * y[2] - MUP * y[1] / d1 - MU * y[1] / d2,
            ]

        r = ode(f).set_integrator("dopri5", rtol=tol, atol=tol, nsteps=10**7)
        r.set_initial_value(Y0, 0.0)
        t0 = time.perf_counter()
        y = r.integrate(PERIOD)
        dt = time.perf_counter() - t0
        err = np.max(np.abs(y - Y0))
        print(f"{tol:>8.0e} {calls[0]:>10} {err:>12.3e} {dt * 1e3:>10.2f}")


if __name__ == "__main__":
    main()
