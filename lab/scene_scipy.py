#!/usr/bin/env python3
"""The paper's hydraulic scene (sweeps/scenes/paper-hydraulic-dt70.toml) in plain SciPy.

A reference for speed and for results: `solve_ivp` RK45 at the same tolerances as the Rust
engine (rtol 1e-6, atol 1e-9), 4 states (x_t, v_t, x_p, v_p), the same physics as
docs/model.md, sections "Contacts" and "Hydraulic module" (sign-correct orifice, adiabatic gas,
Hunt-Crossley contacts clamped at F >= 0, both end-stops, static preload equilibrium).
Contacts are switched inside the right-hand side (no contact events: the plain way a SciPy user
writes it); the sensor is a terminal event, and the robot's kinks are segment boundaries
(sensor -> brake -> stop -> t_end), so the integrator never steps across them.

    .venv/bin/python -m lab.scene_scipy [--runs N] [--dead-time S] [--method M] [--rtol R]

Prints time per run, right-hand-side evaluations, steps per segment of the robot's profile, and
the results to compare with
`cargo run -p cushion-studies --bin run_scene -- sweeps/scenes/paper-hydraulic-dt70.toml`.
`--method` takes any `solve_ivp` method (RK45, DOP853, Radau, BDF, LSODA): the implicit ones
show whether this scene is stiff enough for an implicit method to take fewer steps. `--rtol`
sets rtol (default 1e-6) and atol = rtol / 1000, the scene's own ratio.
"""

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

# Paper Table 1 and the defaults of docs/model.md, "Parameters and defaults" (SI).
L = 0.023
M_T, M_P = 0.048, 0.246
R_P, R_O = 0.020, 0.008
A_P, A_O = math.pi * R_P**2, math.pi * R_O**2
C0, RHO = 3.0, 900.0
P10, VG0, KAPPA = 1000.0, 7.63e-5, 1.4
B, D_DRY = 0.5, 0.0
K_C, CHI_C = 0.6e6, 1.35e6
K_E, CHI_E = 0.6e6, 1.35e6
V_MAX, A_BRAKE = 1.0, 10.0
S_SENSOR, GAP, T_END = 1.5e-3, 1e-3, 0.3
RTOL, ATOL = 1e-6, 1e-9


def hunt_crossley(k, chi, d, dd):
    if d <= 0.0:
        return 0.0
    return max(0.0, d**1.5 * (k + chi * dd))


def gas(s):
    return P10 * (VG0 / (VG0 - A_P * s)) ** KAPPA


def tool_force(s, sd, k_e=K_E, chi_e=CHI_E):
    """G, the lumped module's force on the tool along +x (gas and orifice on the piston,
    viscous friction, both end-stops) at stroke s and its rate sd; the force on the robot is -G."""
    dp = 0.5 * C0 * RHO * (A_P / A_O) ** 2 * sd * abs(sd)
    f_fwd = hunt_crossley(k_e, chi_e, -s, -sd)
    f_back = hunt_crossley(k_e, chi_e, s - L, sd)
    return (gas(s) + dp) * A_P + B * sd + f_back - f_fwd


def make_rhs(robot, k_e=K_E):
    """robot(t) -> (x_r, v_r) on one segment of the profile; k_e the end-stops' stiffness."""

    def rhs(t, y):
        x_t, v_t, x_p, v_p = y
        x_r, v_r = robot(t)
        g = tool_force(x_r - x_t, v_r - v_t, k_e)
        f_c = hunt_crossley(K_C, CHI_C, x_t - x_p, v_t - v_p)
        return [v_t, (g - f_c) / M_T, v_p, f_c / M_P]

    return rhs


def preload_stroke(k_e=K_E):
    """s0 < 0: the static preload equilibrium on the forward stop, k_e (-s0)^1.5 = p1(s0) A_p."""
    return -brentq(lambda d: k_e * d**1.5 - gas(-d) * A_P, 0.0, 1e-2, xtol=1e-16, rtol=1e-15)


def initial_state(s0):
    """The state at t = 0, (x_t, v_t, x_p, v_p): the tool at the preload stroke `s0`
    (`preload_stroke`) riding with the cruising robot, the object GAP ahead of it at rest."""
    return np.array([-s0, V_MAX, -s0 + GAP, 0.0])


def cruise(t):
    return (V_MAX * t, V_MAX)


def sensor_value(t, x_t):
    """The sensor's event function, s - s_sensor, while the robot cruises."""
    return (V_MAX * t - x_t) - S_SENSOR


def after_detection(t_detect, dead_time):
    """The robot's profile after the sensor switched: [(t_a, t_b, robot)] for cruising until the
    brake, braking until the stop, standing until t_end (empty segments dropped)."""
    t_brake = t_detect + dead_time
    t_stop = t_brake + V_MAX / A_BRAKE
    x_b = V_MAX * t_brake
    x_s = x_b + V_MAX**2 / (2 * A_BRAKE)
    braking = lambda t: (x_b + V_MAX * (t - t_brake) - 0.5 * A_BRAKE * (t - t_brake) ** 2, V_MAX - A_BRAKE * (t - t_brake))
    stopped = lambda t: (x_s, 0.0)
    out = []
    for (a, b, robot) in [(t_detect, t_brake, cruise), (t_brake, t_stop, braking), (t_stop, T_END, stopped)]:
        a, b = min(a, T_END), min(b, T_END)
        if b > a:
            out.append((a, b, robot))
    return out


def run(dead_time, method="RK45"):
    """One run: (t_detect, final state, rhs evaluations, x_p0, accepted steps per segment)."""
    s0 = preload_stroke()
    y = initial_state(s0)
    nfev = 0
    steps = []

    # Segment 1: cruising until the sensor switches (terminal event).
    def sensor(t, y):
        return sensor_value(t, y[0])

    sensor.terminal = True
    sensor.direction = 1
    sol = solve_ivp(make_rhs(cruise), (0.0, T_END), y, method=method, rtol=RTOL, atol=ATOL, events=sensor)
    nfev += sol.nfev
    steps.append(len(sol.t) - 1)
    t_detect = sol.t[-1]
    y = sol.y[:, -1]
    # Segments 2-4: cruising until the brake, braking until the stop, standing until t_end.
    for (a, b, robot) in after_detection(t_detect, dead_time):
        sol = solve_ivp(make_rhs(robot), (a, b), y, method=method, rtol=RTOL, atol=ATOL)
        nfev += sol.nfev
        steps.append(len(sol.t) - 1)
        y = sol.y[:, -1]
    return t_detect, y, nfev, -s0 + GAP, steps


def main():
    global RTOL, ATOL
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--dead-time", type=float, default=0.070)
    ap.add_argument("--method", default="RK45", help="a solve_ivp method (default RK45)")
    ap.add_argument("--rtol", type=float, default=1e-6, help="rtol (default 1e-6); atol = rtol / 1000")
    args = ap.parse_args()
    RTOL, ATOL = args.rtol, args.rtol / 1000.0
    run(args.dead_time, args.method)  # warm up
    times = []
    for _ in range(args.runs):
        t0 = time.perf_counter()
        t_detect, y, nfev, x_p0, steps = run(args.dead_time, args.method)
        times.append(time.perf_counter() - t0)
    times.sort()
    print(f"scipy solve_ivp {args.method}, rtol {RTOL:g}, atol {ATOL:g}, hydraulic paper scene, dead time {args.dead_time:g} s")
    print(f"time per run (median of {args.runs}): {times[len(times) // 2] * 1e3:.1f} ms")
    print(f"rhs evaluations: {nfev}")
    print(f"steps: {sum(steps)} (impact to detection {steps[0]}, to the brake {steps[1]}, braking {steps[2]}, standing {steps[3] if len(steps) > 3 else 0})")
    print(f"t_detect: {t_detect:.9f} s")
    print(f"object final velocity: {y[3]:.9f} m/s")
    print(f"object travel: {y[2] - x_p0:.9f} m")


if __name__ == "__main__":
    main()
