#!/usr/bin/env python3
"""Two stiff variants of the paper's hydraulic scene (dead time 70 ms) in plain SciPy.

The scene is `sweeps/scenes/paper-hydraulic-dt70.toml`, with the physics of `lab/scene_scipy.py`
(imported from it: constants, gas, orifice, Hunt-Crossley contacts clamped at F >= 0 and switched
inside the right-hand side, the robot's profile as segments sensor -> brake -> stop -> t_end):

- `steel`: steel end-stops, `stops.stiffness = 1e11` N/m^1.5 (everything else the paper's);
  4 states x_t, v_t, x_p, v_p; the tool starts at its preload equilibrium on the stop,
  -s0 = 5.4e-8 m instead of 0.164 mm.
- `compressible`: oil, `hydraulic.bulk_modulus = 1.5e9` Pa (docs/model.md, "Compressible
  liquid"; `physics::orifice_flow`, `model/forces.rs`): 6 states x_t, v_t, p_m, V_x, x_p, v_p,
  dp_m/dt = beta / (V_m0 - A_p s) (A_p sd - Q), dV_x/dt = Q,
  Q = A_o sqrt(2 / (c0 rho)) dp / (dp^2 + p_tr^2)^(1/4), dp = p_m - p1(V_x),
  p1 = p10 (V_g0 / (V_g0 - V_x))^kappa, p_tr = c0 rho v_cr^2 / 2, v_cr = Re_cr nu / (2 R_o)
  (Re_cr 12, nu 3.2e-5 m^2/s: 0.78 Pa), V_m0 = A_p L + 1.11e-5 m^3; the tool feels p_m A_p.
  Starts at rest: p_m = p1(s0), V_x = A_p s0.

Each scene is solved by `solve_ivp` with Radau, BDF, LSODA (and RK45 for `steel`) at rtol 1e-6
and 1e-7, atol = rtol / 1000 (the engine's ratio), with SciPy's default finite-difference
Jacobians (`--jac analytic` passes the exact Jacobian instead, `--jac both` runs both). Every
run is a child process: it gives up after `--budget` s of solving (60; "did not finish", with
the time it reached), and is killed after `--hard-limit` s (120), so the script always ends.

Reported per run: status; wall time of the whole solve (all segments, dense output on), the
median of 5 runs if one takes under 1 s, of 3 under 10 s, else one run; SciPy's nfev, njev,
nlu and accepted steps, summed over the segments, and `f calls`, every call of the right-hand
side counted in it (Radau and BDF do not count their finite-difference Jacobian's calls in
nfev; a run that did not finish sums nfev, njev, nlu and steps over its finished segments only);
the object's final velocity, the peak robot force F_r = -G (signed, at the largest |F_r|)
and the largest stroke s = x_r - x_t. The peaks are sampled like the engine's (docs/model.md,
"Peaks"): the dense output at every step's ends and at 1/4, 1/2 and 3/4 of every step, then
the largest sample refined by a bounded scalar search (`minimize_scalar`, Brent) over
the two sample intervals around it.

    bash lab/setup_venv.sh      # once: .venv/ with numpy and scipy
    .venv/bin/python -m lab.stiff_scenes_scipy [--scenes steel compressible]
        [--methods Radau BDF LSODA RK45] [--rtols 1e-6 1e-7] [--jac fd|analytic|both]
        [--budget 60] [--hard-limit 120]

Compare with the engine:
`target/release/cushion simulate sweeps/scenes/paper-hydraulic-dt70.toml --set
stops.stiffness=1e11 --set solver.method=rodas --set solver.rtol=1e-7 --set solver.atol=1e-10
--json` (and `--set hydraulic.bulk_modulus=1.5e9` for the compressible scene).
"""

import argparse
import math
import multiprocessing as mp
import os
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from lab.scene_scipy import (  # noqa: E402  (the shared physics)
    A_O, A_P, B, C0, CHI_C, CHI_E, GAP, K_C, K_E, KAPPA, L, M_P, M_T, P10, R_O, RHO, T_END,
    V_MAX, VG0, after_detection, cruise, gas, hunt_crossley, initial_state, make_rhs,
    preload_stroke, sensor_value, tool_force)

DEAD_TIME = 0.070
K_STEEL = 1e11
BETA = 1.5e9
NU, RE_CR = 3.2e-5, 12.0
V_M0 = A_P * L + 1.11e-5
P_TR = 0.5 * C0 * RHO * (RE_CR * NU / (2.0 * R_O)) ** 2
Q_K = A_O * math.sqrt(2.0 / (C0 * RHO))
DP_K = 0.5 * C0 * RHO * (A_P / A_O) ** 2


class OutOfTime(Exception):
    pass


def hc_partials(k, chi, d, dd):
    """(dF/dd, dF/d(dd)) of the clamped Hunt-Crossley force; zero where it does not push."""
    if d <= 0.0 or k + chi * dd <= 0.0:
        return 0.0, 0.0
    r = math.sqrt(d)
    return 1.5 * r * (k + chi * dd), chi * d * r


# ------------------------------------------------- the paper's scene itself (4 states; no CLI)

class Paper:
    """The unmodified paper scene (`paper-hydraulic-dt*.toml`): for lab/work_precision.py."""
    name = "paper"
    n = 4
    i_vp = 3
    k_e = K_E

    def __init__(self):
        self.s0 = preload_stroke(self.k_e)
        self.y0 = initial_state(self.s0)

    def rhs(self, robot):
        return make_rhs(robot, k_e=self.k_e)

    def force_robot(self, t, y, robot):
        x_r, v_r = robot(t)
        return -tool_force(x_r - y[0], v_r - y[1], self.k_e)


# ---------------------------------------------------------------- steel end-stops (4 states)

class Steel:
    name = "steel"
    n = 4
    i_vp = 3

    def __init__(self):
        self.s0 = preload_stroke(K_STEEL)
        self.y0 = initial_state(self.s0)

    def rhs(self, robot):
        return make_rhs(robot, k_e=K_STEEL)

    def force_robot(self, t, y, robot):
        x_r, v_r = robot(t)
        return -tool_force(x_r - y[0], v_r - y[1], K_STEEL)

    def jac(self, robot):
        def jac(t, y):
            x_t, v_t, x_p, v_p = y
            x_r, v_r = robot(t)
            s, sd = x_r - x_t, v_r - v_t
            p1 = gas(s)
            ff_d, ff_dd = hc_partials(K_STEEL, CHI_E, -s, -sd)
            fb_d, fb_dd = hc_partials(K_STEEL, CHI_E, s - L, sd)
            g_s = KAPPA * p1 * A_P * A_P / (VG0 - A_P * s) + fb_d + ff_d
            g_sd = 2.0 * DP_K * abs(sd) * A_P + B + fb_dd + ff_dd
            c_d, c_dd = hc_partials(K_C, CHI_C, x_t - x_p, v_t - v_p)
            return [[0.0, 1.0, 0.0, 0.0],
                    [(-g_s - c_d) / M_T, (-g_sd - c_dd) / M_T, c_d / M_T, c_dd / M_T],
                    [0.0, 0.0, 0.0, 1.0],
                    [c_d / M_P, c_dd / M_P, -c_d / M_P, -c_dd / M_P]]
        return jac


# ------------------------------------------------------------- compressible liquid (6 states)

def gas_v(v_x):
    """Gas pressure with the liquid volume v_x moved through the orifice."""
    return P10 * (VG0 / (VG0 - v_x)) ** KAPPA


def orifice_flow(dp):
    return Q_K * dp / math.sqrt(math.sqrt(dp * dp + P_TR * P_TR))


def stops_force(s, sd):
    """End-stops' force on the tool (back stop +, forward stop -)."""
    return hunt_crossley(K_E, CHI_E, s - L, sd) - hunt_crossley(K_E, CHI_E, -s, -sd)


class Compressible:
    name = "compressible"
    n = 6
    i_vp = 5

    def __init__(self):
        self.s0 = preload_stroke(K_E)
        x_t0 = -self.s0
        self.y0 = np.array([x_t0, V_MAX, gas(self.s0), A_P * self.s0, x_t0 + GAP, 0.0])

    def rhs(self, robot):
        def rhs(t, y):
            x_t, v_t, p_m, v_x, x_p, v_p = y
            x_r, v_r = robot(t)
            s, sd = x_r - x_t, v_r - v_t
            q = orifice_flow(p_m - gas_v(v_x))
            g = p_m * A_P + B * sd + stops_force(s, sd)
            f_c = hunt_crossley(K_C, CHI_C, x_t - x_p, v_t - v_p)
            return [v_t, (g - f_c) / M_T, BETA / (V_M0 - A_P * s) * (A_P * sd - q), q, v_p, f_c / M_P]
        return rhs

    def force_robot(self, t, y, robot):
        x_r, v_r = robot(t)
        s, sd = x_r - y[0], v_r - y[1]
        return -(y[2] * A_P + B * sd + stops_force(s, sd))

    def jac(self, robot):
        def jac(t, y):
            x_t, v_t, p_m, v_x, x_p, v_p = y
            x_r, v_r = robot(t)
            s, sd = x_r - x_t, v_r - v_t
            p1 = gas_v(v_x)
            dp = p_m - p1
            w = dp * dp + P_TR * P_TR
            q = Q_K * dp / math.sqrt(math.sqrt(w))
            q_dp = Q_K * (0.5 * dp * dp + P_TR * P_TR) / (w * math.sqrt(math.sqrt(w)))
            p1_v = KAPPA * p1 / (VG0 - v_x)
            ff_d, ff_dd = hc_partials(K_E, CHI_E, -s, -sd)
            fb_d, fb_dd = hc_partials(K_E, CHI_E, s - L, sd)
            g_s, g_sd = fb_d + ff_d, B + fb_dd + ff_dd
            c_d, c_dd = hc_partials(K_C, CHI_C, x_t - x_p, v_t - v_p)
            vm = V_M0 - A_P * s
            bv = BETA / vm
            pm_s = bv * A_P / vm * (A_P * sd - q)
            return [[0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
                    [(-g_s - c_d) / M_T, (-g_sd - c_dd) / M_T, A_P / M_T, 0.0, c_d / M_T, c_dd / M_T],
                    [-pm_s, -bv * A_P, -bv * q_dp, bv * q_dp * p1_v, 0.0, 0.0],
                    [0.0, 0.0, q_dp, -q_dp * p1_v, 0.0, 0.0],
                    [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
                    [c_d / M_P, c_dd / M_P, 0.0, 0.0, -c_d / M_P, -c_dd / M_P]]
        return jac


SCENES = {"steel": Steel, "compressible": Compressible}


# ------------------------------------------------------------------------------ one run

def solve(scene, method, rtol, analytic, budget, dead_time=DEAD_TIME, atol=None):
    """One run to t_end. Returns (pieces, stats): pieces [(OdeSolution, robot, t_steps)]."""
    atol = rtol / 1000.0 if atol is None else atol
    deadline = time.perf_counter() + budget
    calls = [0]
    stats = dict(nfev=0, njev=0, nlu=0, steps=0, status="ok", t_reached=0.0, t_detect=None)

    def counted(f):
        def g(t, y):
            calls[0] += 1
            if calls[0] & 255 == 0 and time.perf_counter() > deadline:
                stats["t_reached"] = t
                raise OutOfTime
            return f(t, y)
        return g

    def sensor(t, y):
        return sensor_value(t, y[0])

    sensor.terminal = True
    sensor.direction = 1
    pieces = []
    y = scene.y0
    segments = [(0.0, T_END, cruise)]
    try:
        while segments:
            a, b, robot = segments.pop(0)
            kw = dict(method=method, rtol=rtol, atol=atol, dense_output=True)
            if analytic and method != "RK45":
                kw["jac"] = scene.jac(robot)
            if a == 0.0:
                kw["events"] = sensor
            sol = solve_ivp(counted(scene.rhs(robot)), (a, b), y, **kw)
            for k in ("nfev", "njev", "nlu"):
                stats[k] += getattr(sol, k)
            stats["steps"] += len(sol.t) - 1
            pieces.append((sol.sol, robot, sol.t))
            y = sol.y[:, -1]
            stats["t_reached"] = sol.t[-1]
            if sol.status < 0:
                stats["status"] = "failed: " + sol.message
                break
            if a == 0.0 and sol.status == 1:
                stats["t_detect"] = sol.t[-1]
                segments = after_detection(sol.t[-1], dead_time)
    except OutOfTime:
        stats["status"] = "did not finish"
    stats["f_calls"] = calls[0]
    stats["y_end"] = y
    return pieces, stats


def peaks(scene, pieces):
    """(signed F_r at the largest |F_r|, largest stroke), sampled and refined (see the doc)."""
    best = {"f": (-1.0, None), "s": (-math.inf, None)}
    for piece_no, (ode, robot, ts) in enumerate(pieces):
        tt = np.concatenate([(ts[:-1, None] + np.diff(ts)[:, None] * np.array([0.0, 0.25, 0.5, 0.75])).ravel(),
                             ts[-1:]])
        ys = ode(tt)
        fr = np.array([abs(scene.force_robot(t, ys[:, i], robot)) for i, t in enumerate(tt)])
        st = np.array([robot(t)[0] for t in tt]) - ys[0]
        for key, vals in (("f", fr), ("s", st)):
            i = int(np.argmax(vals))
            if vals[i] > best[key][0]:
                best[key] = (vals[i], (piece_no, tt[i], tt[max(i - 1, 0)], tt[min(i + 1, len(tt) - 1)]))
    out = {}
    for key, (val, (piece_no, t_i, lo, hi)) in best.items():
        ode, robot, _ = pieces[piece_no]
        if key == "f":
            q = lambda t: scene.force_robot(t, ode(t), robot)
            r = minimize_scalar(lambda t: -abs(q(t)), bounds=(lo, hi), method="bounded",
                                options={"xatol": 1e-13})
            t_pk = r.x if abs(q(r.x)) > val else t_i
            out["peak_robot_force"], out["t_peak"] = q(t_pk), t_pk
        else:
            q = lambda t: robot(t)[0] - ode(t)[0]
            r = minimize_scalar(lambda t: -q(t), bounds=(lo, hi), method="bounded",
                                options={"xatol": 1e-13})
            out["max_stroke"] = max(val, q(r.x))
    return out


def child(scene_name, method, rtol, analytic, budget, queue):
    # trial stages far off (a stroke past the gas volume, FD factors overflowing) warn; the
    # solver rejects those steps itself
    warnings.simplefilter("ignore", RuntimeWarning)
    scene = SCENES[scene_name]()
    t0 = time.perf_counter()
    pieces, stats = solve(scene, method, rtol, analytic, budget)
    times = [time.perf_counter() - t0]
    if stats["status"] == "ok":
        stats.update(peaks(scene, pieces))
        stats["object_final_velocity"] = stats["y_end"][scene.i_vp]
        repeats = 4 if times[0] < 1.0 else 2 if times[0] < 10.0 else 0
        for _ in range(repeats):
            t0 = time.perf_counter()
            solve(scene, method, rtol, analytic, budget)
            times.append(time.perf_counter() - t0)
    stats["seconds"] = sorted(times)[len(times) // 2]
    stats["runs"] = len(times)
    del stats["y_end"]
    queue.put(stats)


def run_in_child(scene_name, method, rtol, analytic, budget, hard_limit):
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    p = ctx.Process(target=child, args=(scene_name, method, rtol, analytic, budget, queue))
    t0 = time.perf_counter()
    p.start()
    try:
        stats = queue.get(timeout=hard_limit)
    except Exception:
        stats = dict(status=f"killed after {hard_limit:g} s", seconds=time.perf_counter() - t0, runs=1)
        p.kill()
    p.join()
    return stats


def fmt(x, f):
    return "-" if x is None else format(x, f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=["steel", "compressible"], choices=list(SCENES))
    ap.add_argument("--methods", nargs="+", default=["Radau", "BDF", "LSODA", "RK45"])
    ap.add_argument("--rtols", nargs="+", type=float, default=[1e-6, 1e-7])
    ap.add_argument("--jac", choices=["fd", "analytic", "both"], default="fd")
    ap.add_argument("--budget", type=float, default=60.0, help="s of solving before giving up")
    ap.add_argument("--hard-limit", type=float, default=120.0, help="s before a run is killed")
    args = ap.parse_args()
    jacs = {"fd": [False], "analytic": [True], "both": [False, True]}[args.jac]
    print(f"scipy solve_ivp on the paper's hydraulic scene, dead time {DEAD_TIME:g} s; atol = rtol / 1000; "
          f"load average {os.getloadavg()[0]:.2f}")
    print("| scene | method | jac | rtol | status | s (runs) | nfev | f calls | njev | nlu | steps "
          "| t_detect | object final velocity | peak robot force | max stroke |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for scene_name in args.scenes:
        for method in args.methods:
            if method in ("RK45", "DOP853", "RK23") and scene_name == "compressible":
                continue  # explicit: does not finish (docs/model.md, "Compressible liquid")
            for analytic in jacs:
                if analytic and method in ("RK45", "DOP853", "RK23"):
                    continue
                for rtol in args.rtols:
                    st = run_in_child(scene_name, method, rtol, analytic, args.budget, args.hard_limit)
                    status = st["status"]
                    if status != "ok" and "t_reached" in st:
                        status += f" (t = {st['t_reached']:.4g} s)"
                    print(f"| {scene_name} | {method} | {'exact' if analytic else 'FD'} | {rtol:g} | {status} "
                          f"| {st['seconds']:.3f} ({st['runs']}) | {st.get('nfev', '-')} | {st.get('f_calls', '-')} "
                          f"| {st.get('njev', '-')} | {st.get('nlu', '-')} | {st.get('steps', '-')} "
                          f"| {fmt(st.get('t_detect'), '.9f')} | {fmt(st.get('object_final_velocity'), '.9f')} "
                          f"| {fmt(st.get('peak_robot_force'), '.6f')} | {fmt(st.get('max_stroke'), '.9e')} |",
                          flush=True)


if __name__ == "__main__":
    main()
