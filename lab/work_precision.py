#!/usr/bin/env python3
"""Work-precision study: error against work (wall time, right-hand-side evaluations) for the
engine's methods and for peers, on the paper's scenes, two stiff variants and a smooth problem.

    # once (and after changing the engine): .venv/ with SciPy, the peers (numba, CyRK) and the
    # other benchmark dependencies of lab/requirements.txt, and this checkout's cushion
    # package built into it by maturin (minutes)
    bash lab/setup_venv.sh
    # the study (about 9 min on the 2-vCPU Intel VM, 1 min of it compiling CyRK; --quick: a smoke run of under a minute)
    .venv/bin/python -m lab.work_precision [--quick] [--scenes NAME...] [--no-charts]

Needs numpy, scipy, pandas, matplotlib and the `cushion` package; `numba` and `CyRK` for the
compiled peer (skipped with a note if missing; NumbaLSODA does not build here: it needs a
Fortran compiler); lab/setup_venv.sh installs them all, at the versions of
lab/requirements.txt. Writes lab/results/work_precision.csv (one row per scene, method, setting and error
measure), lab/results/work_precision.json (machine, commit, date, versions, the references and their
agreement, the interpolated tables: the time and evaluations where the error first crosses each
level from 1e-4 to 1e-9, `at_error`, and where it crosses it for the last time, so that every
costlier setting stays below it, `at_error_settled`) and docs/figures/work-precision-{time,evals}.svg;
prints, last, the issue's speed targets read off those tables (`target_lines`).
`python3 -m lab.study_tables [JSON]` prints docs/performance.md's tables from the JSON.

Scenes: the five paper scenes (sweeps/scenes/paper-*.toml); `steel-stops` (paper-hydraulic-dt70
with stops.stiffness = 1e11); `compressible` (paper-hydraulic-dt70 with hydraulic.bulk_modulus =
1.5e9; explicit methods are not run there: "failed (explicit)"); `oscillator`, a damped linear
oscillator x'' + 2 zeta w x' + w^2 x = 0 with a closed form, which the engine's integrator runs
alone (`lab/studies/src/bin/oscillator.rs`, built by this script: no events, no
observers, the final state only, timed in-process in Rust).

Error measures: object_final_velocity (m/s), peak_robot_force (N), t_detect (s), and
trajectory_velocity (m/s: the largest error of the tool's and the object's speeds at 99 fixed
times, every 3 ms), absolute, against a reference computed two ways and printed side by side: the hydraulic scenes, the steel stops: the
engine's dp5 at rtol 1e-13 / atol 1e-16 and SciPy's DOP853 (solve_ivp) at the same tolerances on
the Python model of lab/scene_scipy.py / stiff_scenes_scipy.py; the compressible scene: the
engine's rodas at 1e-12 / 1e-15 and SciPy's Radau (exact Jacobian) at 1e-12 / 1e-15; the bistable
and rigid scenes (engine only): the engine's dp5 at 1e-13 and rodas at 1e-11. Each run is measured
against the reference of its own model (the engine's runs against the engine's, the Python
model's against SciPy's), and an error is marked `resolved` only if it exceeds ten times the
references' disagreement (the charts drop unresolved points and draw that floor).

Work: wall time per run, ours and the peers' alike, from about 0.2 s of repeats (at most 2,000;
a peer run over 1 s is timed once) in five interleaved rounds over all of a scene's settings:
the smallest of the rounds' medians (`time_interleaved`: this VM's speed wanders over seconds
to minutes, and only ever slows a run down) (the engine: in-process `cushion.simulate(scene,
trajectory=False)` calls from a `cushion.Scene` made before the clock starts, as the peers'
scenes are, nothing subtracted; SciPy: the whole solve of all segments, dense output on for
solve_ivp, peaks not included); right-hand-side evaluations
(`stats["rhs_evals"]`; the peers: every call of the right-hand side, finite-difference Jacobians
and event location included).

The engine's methods: dp5 and dop853 (rtol 1e-3 to 1e-12, atol = rtol / 1000; on the steel
stops also at quarter decades from 1e-3 to 1e-7, as CyRK's two, `DENSE_GRID`: there the final
speed's error jumps about from one rtol to the next), rodas and auto (to 1e-10), rk4 and euler
(fixed steps), all at the scene's defaults (the energy ledger on: four
more states, integrated, their errors added to the error norm's sum but not to its count);
dp5 and dop853 with `energy.ledger = false`
("ledger off"), which compute what the peers do; and dp5 with `solver.ringing_tail = false`
("ringing tail off": the tool's last ringing on its stop integrated, not written in closed form).

Peers (the Python model: 4 states, contacts switched inside the right-hand side, the robot's
kinks as segment boundaries, the sensor found by root-finding): SciPy solve_ivp RK45, DOP853,
Radau, LSODA (finite-difference Jacobians, as a user gets them); Hairer's Fortran DOPRI5 and
DOP853 through scipy.integrate.ode (the sensor: `solout` stops at the first step past it, then
Brent's method on re-integrations from the step before); CyRK's C++ DOP853 and RK45 with a
numba-compiled right-hand side (`cyrk_peer.py`, `nbsolve2_ivp`; the cruise in 0.5 ms chunks, each restarted with
the last step size (at most half a chunk: CyRK's limit), until a step passes the sensor, then as for Hairer's). Hairer's and CyRK's
runs report the final speed and t_detect only (no dense output to find the peak force or the
fixed-time samples from). The fixed-time samples: the engine's uniform trajectory samples
(`sample_interval` 3 ms, read off its dense output, from a second, untimed run of the same
setting: recording does not change the steps), and solve_ivp's dense output; the oscillator has
no trajectory measure.
"""

import argparse
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import time
import warnings

try:
    import numpy as np
    from scipy.integrate import ode, solve_ivp
    from scipy.optimize import brentq
except ImportError as e:
    sys.exit(f"{e}: the study's environment is made by `bash lab/setup_venv.sh` (then run it with .venv/bin/python)")

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
from lab import scene_scipy as ss  # noqa: E402
from lab import cyrk_peer  # noqa: E402
from lab.study_tables import target_lines  # noqa: E402
from lab import stiff_scenes_scipy as sts  # noqa: E402

try:
    import cushion  # noqa: E402
except ImportError as e:
    sys.exit(f"{e}: `bash lab/setup_venv.sh` builds the package into .venv/ (then run the study with .venv/bin/python)")

MEASURES = ("object_final_velocity", "peak_robot_force", "t_detect")  # read off the summary
# the largest error of the tool's and the object's speeds (m/s) at SAMPLE_TIMES
TRAJECTORY = "trajectory_velocity"
ALL_MEASURES = MEASURES + (TRAJECTORY,)
SAMPLE_INTERVAL = ss.T_END / 100
# k * interval, as the engine's recorder computes its uniform sample times (the same floats)
SAMPLE_TIMES = np.arange(1, 100) * SAMPLE_INTERVAL
DT70 = "sweeps/scenes/paper-hydraulic-dt70.toml"
SCENES = {
    # name: (scene file, overrides, python model (class, dead time) or None, stiff)
    "paper-hydraulic-dt70": (DT70, {}, (sts.Paper, 0.070), False),
    "paper-hydraulic-dt10": ("sweeps/scenes/paper-hydraulic-dt10.toml", {}, (sts.Paper, 0.010), False),
    "paper-bistable-dt70": ("sweeps/scenes/paper-bistable-dt70.toml", {}, None, False),
    "paper-bistable-dt10": ("sweeps/scenes/paper-bistable-dt10.toml", {}, None, False),
    "paper-rigid": ("sweeps/scenes/paper-rigid.toml", {}, None, False),
    "steel-stops": (DT70, {"stops.stiffness": 1e11}, (sts.Steel, 0.070), False),
    "compressible": (DT70, {"hydraulic.bulk_modulus": 1.5e9}, (sts.Compressible, 0.070), True),
    "oscillator": None,
}
# the engine without its energy ledger (four states instead of eight): the work the peers do,
# which compute no energy balance
VARIANTS = {"dp5_no_ledger": ("dp5", {"energy.ledger": False}),
            "dop853_no_ledger": ("dop853", {"energy.ledger": False}),
            # the tool's ringing on its stop integrated to t_end, not written in closed form: what
            # the ringing tail costs the trajectory (it is built to keep the summary, not the
            # ringing's phase, within the tolerance)
            "dp5_no_tail": ("dp5", {"solver.ringing_tail": False})}
EXPLICIT_OURS = ("dp5", "dop853", "rk4", "euler", "dp5_no_ledger", "dop853_no_ledger", "dp5_no_tail")
EXPLICIT_PEERS = ("RK45", "DOP853", "hairer-dopri5", "hairer-dop853", "cyrk-DOP853", "cyrk-RK45")

# the damped linear oscillator: x'' + 2 zeta w x' + w^2 x = 0, x(0) = 1, x'(0) = 0, to T
OSC_W, OSC_ZETA, OSC_T = 2 * math.pi * 10.0, 0.05, 1.0


def osc_exact(t):
    wd = OSC_W * math.sqrt(1 - OSC_ZETA**2)
    e = math.exp(-OSC_ZETA * OSC_W * t)
    return (e * (math.cos(wd * t) + OSC_ZETA * OSC_W / wd * math.sin(wd * t)),
            -e * OSC_W**2 / wd * math.sin(wd * t))


def osc_rhs(t, y):
    return [y[1], -2 * OSC_ZETA * OSC_W * y[1] - OSC_W**2 * y[0]]


OSC_BIN = os.path.join(ROOT, os.environ.get("CARGO_TARGET_DIR", "target"), "release", "oscillator")


def engine_oscillator(settings):
    """The integrator alone on the oscillator: {(method, label): result dict} for settings
    [(method, label, dict(rtol=..) or dict(h=..))], from one run of the Rust study binary."""
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "cushion-studies", "--bin", "oscillator"],
                   cwd=ROOT, check=True)
    argv = [f"{m}={'h%r' % st['h'] if 'h' in st else repr(st['rtol'])}" for m, _, st in settings]
    out = subprocess.run([OSC_BIN, repr(OSC_W), repr(OSC_ZETA), repr(OSC_T), *argv],
                         capture_output=True, text=True, check=True).stdout.split("\n")
    res = {}
    for (m, label, _), line in zip(settings, out):
        _, _, status, v, secs, evals, repeats = line.split()
        ok = status == "Success"
        res[(m, label)] = dict(status="ok" if ok else f"failed: {status}", seconds=float(secs),
                               rhs_evals=int(evals), repeats=int(repeats),
                               **({"values": {"object_final_velocity": float(v)}} if ok else {}))
    return res


def log(*a):
    print(*a, flush=True)


def sci(x):
    """1e-6, 3e-5, and two digits where two are needed: 5.6e-7 (the denser grid below)."""
    mantissa, exponent = f"{x:.1e}".split("e")
    text = (mantissa[:-2] if mantissa.endswith(".0") else mantissa) + "e" + exponent
    return text.replace("e-0", "e-").replace("e+0", "e+")


# Where one method's error jumps about from one rtol to the next (the steel stops' final speed,
# settled in the first 80 ms: docs/performance.md), a decade grid shows each method a few draws,
# and the error level where one is cheaper than another is partly which draws it got. There,
# the fast methods (ours and the compiled peer's) also run at quarter decades from 1e-3 to 1e-7,
# and the table also reads the work from which the error stays below a level (`interpolate`,
# `settled`).
DENSE_GRID = {"steel-stops": [10.0 ** (-3 - k / 4) for k in range(17)]}
DENSE_METHODS = ("dp5", "dop853", "dp5_no_ledger", "dop853_no_ledger", "cyrk-DOP853", "cyrk-RK45")


def rtol_grid(name, method, decades):
    """The rtols `method` runs at on scene `name`: the decades, and the denser grid where the
    scene has one and the method is fast enough, from loose to tight."""
    extra = DENSE_GRID.get(name, []) if method in DENSE_METHODS else []
    merged = list(decades) + [r for r in extra if not any(math.isclose(r, d, rel_tol=1e-9) for d in decades)]
    return sorted(merged, reverse=True)


# ------------------------------------------------------------------------------ the engine

def engine_once(name, method, rtol=None, atol=None, h=None, record=False):
    """One run of a scene as a function; `record`: with its uniform samples at SAMPLE_INTERVAL."""
    path, over, _, _ = SCENES[name]
    method, extra = VARIANTS.get(method, (method, {}))
    st = dict(over, **extra)
    kw = dict(method=method, trajectory=record)
    if record:
        kw["sample_interval"] = SAMPLE_INTERVAL
    if h is not None:
        st["solver.fixed_step"] = h
    else:
        kw.update(rtol=rtol, atol=atol)
    # read and checked once, outside the timing, as the peers' scenes are built before theirs
    scene = cushion.Scene(os.path.join(ROOT, path), set=st)
    return lambda: cushion.simulate(scene, **kw)


def engine_samples(name, method, setting):
    """The tool's and the object's speeds at SAMPLE_TIMES, (2, 99), from a run that records
    its trajectory (NaN where the scene has no such body); None if a sample time is missing."""
    run = engine_once(name, method, **setting, record=True)()
    idx = np.searchsorted(run.t, SAMPLE_TIMES)
    if np.any(idx >= run.t.size) or np.any(run.t[np.minimum(idx, run.t.size - 1)] != SAMPLE_TIMES):
        return None
    return np.vstack([run.v_t[idx], run.v_p[idx]])


def trajectory_error(samples, ref):
    """The largest |speed - reference| over the sample times and the bodies the scene has."""
    d = np.abs(np.asarray(samples) - np.asarray(ref))
    return float(np.nanmax(d)) if np.isfinite(d).any() else float("nan")


def repeats(first_seconds, target, lo, hi):
    """How many runs to time: about `target` seconds of them, within [lo, hi]."""
    return int(min(hi, max(lo, target / max(first_seconds, 1e-9))))


def time_interleaved(points, args):
    """Time every point of one scene, ours and the peers' alike, in `args.rounds` interleaved
    rounds: each round visits the points in a new (seeded) order and times each over about
    `target / rounds` seconds; a point's time is the smallest of its rounds' medians. This VM's
    speed wanders by a fifth to a half over seconds to minutes (the same run, instruction for
    instruction, takes 160 to 250 µs from one second to the next), so settings timed back to
    back would compare different machine states, and a slow minute would fall whole on one
    method; interleaved, every point meets the quiet moments too, and since a disturbance only
    ever slows a run, the quietest round is the fairest estimate of each. `points`: result dicts
    whose `_timer()` runs once and returns its seconds and `_first` the first run's; each gets
    `seconds` and `repeats` (the runs timed, all rounds)."""
    import random
    timed_points = [p for p in points if p.get("_timer") is not None]
    for p in timed_points:
        p["_medians"], p["repeats"] = [], 0
    per_round, most = args.target / args.rounds, max(1, args.most // args.rounds)
    for k in range(args.rounds):
        order = list(timed_points)
        random.Random(k).shuffle(order)
        for p in order:
            n = repeats(p["_first"], per_round, 1, most)
            p["_medians"].append(float(np.median([p["_timer"]() for _ in range(n)])))
            p["repeats"] += n
    for p in points:
        if p.get("_timer") is not None:
            p["seconds"] = min(p["_medians"])
        for key in ("_timer", "_first", "_medians"):
            p.pop(key, None)


def engine_point(name, method, setting, args):
    """One engine setting: dict(status, values, seconds, rhs_evals, repeats), with its timer
    for `time_interleaved`."""
    try:
        fn = engine_once(name, method, **setting)
        t0 = time.perf_counter()
        run = fn()
        first = time.perf_counter() - t0
    except cushion.ConfigError as e:
        return dict(status=f"failed: {e}".splitlines()[0][:120])
    s = run.summary
    if s["status"] != "ok":
        return dict(status=f"failed: {s['status']}", rhs_evals=s["stats"]["rhs_evals"], seconds=first)
    values = {m: s[m] for m in MEASURES}
    samples = engine_samples(name, method, setting)
    if samples is not None:
        values[TRAJECTORY] = samples

    def timer():
        t0 = time.perf_counter()
        fn()
        return time.perf_counter() - t0

    return dict(status="ok", values=values, seconds=first, rhs_evals=s["stats"]["rhs_evals"], repeats=1,
                _timer=timer, _first=first)


def engine_has_dop853():
    try:
        cushion.simulate(os.path.join(ROOT, DT70), method="dop853", trajectory=False)
        return True
    except cushion.ConfigError:
        return False


# ----------------------------------------------------------------- SciPy solve_ivp (Python model)

def scipy_ivp_once(name, method, rtol, atol, budget, analytic=False):
    cls, dead_time = SCENES[name][2]
    scene = cls()
    t0 = time.perf_counter()
    pieces, st = sts.solve(scene, method, rtol, analytic, budget, dead_time=dead_time, atol=atol)
    secs = time.perf_counter() - t0
    if st["status"] != "ok":
        return dict(status="failed: " + st["status"], seconds=secs, rhs_evals=st["f_calls"])
    vals = dict(sts.peaks(scene, pieces))
    vals["object_final_velocity"] = st["y_end"][scene.i_vp]
    vals["t_detect"] = st["t_detect"]
    vals[TRAJECTORY] = ivp_samples(scene, pieces)
    return dict(status="ok", values={m: vals[m] for m in ALL_MEASURES}, seconds=secs, rhs_evals=st["f_calls"])


def ivp_samples(scene, pieces):
    """The tool's and the object's speeds at SAMPLE_TIMES from solve_ivp's dense output, (2, 99)."""
    out = np.full((2, SAMPLE_TIMES.size), np.nan)
    for dense, _, ts in pieces:
        inside = (SAMPLE_TIMES >= ts[0]) & (SAMPLE_TIMES <= ts[-1])
        if inside.any():
            ys = dense(SAMPLE_TIMES[inside])
            out[0, inside], out[1, inside] = ys[1], ys[scene.i_vp]
    return out


def osc_ivp_once(method, rtol, atol, budget):
    calls = [0]

    def f(t, y):
        calls[0] += 1
        return osc_rhs(t, y)

    t0 = time.perf_counter()
    sol = solve_ivp(f, (0.0, OSC_T), [1.0, 0.0], method=method, rtol=rtol, atol=atol)
    secs = time.perf_counter() - t0
    if sol.status != 0:
        return dict(status="failed: " + sol.message, seconds=secs, rhs_evals=calls[0])
    return dict(status="ok", values={"object_final_velocity": sol.y[1, -1]}, seconds=secs, rhs_evals=calls[0])


# ------------------------------------------------ Hairer's DOPRI5 / DOP853 (scipy.integrate.ode)

class Stop(Exception):
    pass


def counted(f, calls, deadline):
    def g(t, y):
        calls[0] += 1
        if calls[0] & 1023 == 0 and time.perf_counter() > deadline:
            raise Stop
        return f(t, y)
    return g


def hairer_advance(f, integ, rtol, atol, t0, y0, t1, solout=None):
    r = ode(f).set_integrator(integ, rtol=rtol, atol=atol, nsteps=10**8)
    if solout is not None:
        r.set_solout(solout)
    r.set_initial_value(y0, t0)
    y = r.integrate(t1)
    if not r.successful():
        raise RuntimeError(f"{integ} failed at t = {r.t}")
    return r.t, np.array(y)


def locate(advance, ta, ya, tb):
    """t_detect in (ta, tb] and the state there, the state at t found by integrating from ta."""
    def g(t):
        if t == ta:
            return ss.sensor_value(ta, ya[0])
        return ss.sensor_value(t, advance(ta, ya, t)[0])
    if g(tb) <= 0.0:  # the re-integration does not see the crossing: take the step's end
        return tb, advance(ta, ya, tb)
    td = brentq(g, ta, tb, xtol=1e-17, rtol=1e-15)
    return td, advance(ta, ya, td)


def robot_segments(t_detect, dead_time):
    """[(a, b, mode, t_brake, x_b, x_s)]: cruise to the brake, braking, standing (clipped)."""
    t_brake = t_detect + dead_time
    t_stop = t_brake + ss.V_MAX / ss.A_BRAKE
    x_b = ss.V_MAX * t_brake
    x_s = x_b + ss.V_MAX**2 / (2 * ss.A_BRAKE)
    out = []
    for a, b, mode in ((t_detect, t_brake, 0), (t_brake, t_stop, 1), (t_stop, ss.T_END, 2)):
        a, b = min(a, ss.T_END), min(b, ss.T_END)
        if b > a:
            out.append((a, b, mode, t_brake, x_b, x_s))
    return out


def hairer_once(name, integ, rtol, atol, budget):
    calls = [0]
    deadline = time.perf_counter() + budget
    t0 = time.perf_counter()
    try:
        if name == "oscillator":
            _, y = hairer_advance(counted(osc_rhs, calls, deadline), integ, rtol, atol, 0.0, [1.0, 0.0], OSC_T)
            return dict(status="ok", values={"object_final_velocity": y[1]}, seconds=time.perf_counter() - t0,
                        rhs_evals=calls[0])
        cls, dead_time = SCENES[name][2]
        scene = cls()
        f = counted(scene.rhs(ss.cruise), calls, deadline)
        last = {}

        def solout(t, y):
            if ss.sensor_value(t, y[0]) > 0.0:
                return -1
            last["t"], last["y"] = t, np.array(y)
            return 0

        tb, _ = hairer_advance(f, integ, rtol, atol, 0.0, scene.y0, ss.T_END, solout)
        adv = lambda ta, ya, t: hairer_advance(f, integ, rtol, atol, ta, ya, t)[1]
        td, y = locate(adv, last["t"], last["y"], tb)
        for (a, b, robot) in ss.after_detection(td, dead_time):
            _, y = hairer_advance(counted(scene.rhs(robot), calls, deadline), integ, rtol, atol, a, y, b)
    except Stop:
        return dict(status=f"failed: time limit {budget:g} s", seconds=time.perf_counter() - t0, rhs_evals=calls[0])
    except RuntimeError as e:
        return dict(status=f"failed: {e}", seconds=time.perf_counter() - t0, rhs_evals=calls[0])
    return dict(status="ok", values={"object_final_velocity": y[scene.i_vp], "t_detect": td},
                seconds=time.perf_counter() - t0, rhs_evals=calls[0])


# ------------------------------------------------------- CyRK with a numba-compiled right-hand side

CYRK = None  # filled by cyrk_setup(): a cyrk_peer.Peer, or the reason it is missing


def cyrk_setup():
    """Compile the compiled peer (`cyrk_peer.py`), or keep the reason it is missing."""
    global CYRK
    peer, reason = cyrk_peer.setup(OSC_W, OSC_ZETA)
    CYRK = reason if peer is None else peer
    if peer is None:
        return
    # compile now, outside any timing
    for m in ("DOP853", "RK45"):
        cyrk_once("oscillator", "cyrk-" + m, 1e-6, 1e-9, 60.0)
        cyrk_once("paper-hydraulic-dt70", "cyrk-" + m, 1e-6, 1e-9, 60.0)


def cyrk_once(name, method, rtol, atol, budget):
    """One CyRK run, driven from numba (no time limit inside: CyRK's runs here take milliseconds)."""
    meth = method.split("-", 1)[1]
    counter = np.zeros(1, np.int64)
    args = cyrk_peer.args_for(counter)
    t0 = time.perf_counter()
    if name == "oscillator":
        ok, v = CYRK.osc(CYRK.addr["osc"], meth, np.array([1.0, 0.0]), args, rtol, atol, OSC_T)
        td = None
    else:
        cls, dead_time = SCENES[name][2]
        scene = cls()
        args[4] = sts.K_STEEL if cls is sts.Steel else ss.K_E
        ok, v, td = CYRK.run(CYRK.addr["scene"], meth, scene.y0, args, rtol, atol, dead_time,
                                cyrk_peer.CHUNK, ss.T_END)
    secs = time.perf_counter() - t0
    if not ok:
        return dict(status="failed: CyRK did not succeed", seconds=secs, rhs_evals=int(counter[0]))
    vals = {"object_final_velocity": v} if td is None else {"object_final_velocity": v, "t_detect": td}
    return dict(status="ok", values=vals, seconds=secs, rhs_evals=int(counter[0]))


def peer_point(name, method, rtol, args):
    """One peer run: dict like engine_point's (with a timer unless the run took over
    `peer_slow` seconds)."""
    atol = rtol / 1000.0
    budget = args.budget
    if method.startswith("hairer-"):
        fn = lambda: hairer_once(name, method.split("-", 1)[1], rtol, atol, budget)
    elif method.startswith("cyrk-"):
        fn = lambda: cyrk_once(name, method, rtol, atol, budget)
    elif name == "oscillator":
        fn = lambda: osc_ivp_once(method, rtol, atol, budget)
    else:
        fn = lambda: scipy_ivp_once(name, method, rtol, atol, budget)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            r = fn()
        except Exception as e:  # noqa: BLE001  (e.g. a NaN state handed to the next segment)
            return dict(status=f"failed: {type(e).__name__}: {e}"[:120])
        if r["status"] == "ok" and not all(np.isfinite(v).all() for v in r["values"].values()):
            r["status"] = "failed: non-finite result"
        if r["status"] != "ok":
            return r
    r["repeats"] = 1
    if r["seconds"] <= args.peer_slow:  # a slower run is timed once, here

        def timer():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return fn()["seconds"]

        r["_timer"], r["_first"] = timer, r["seconds"]
    return r


# ------------------------------------------------------------------------------ references

def references(names, args):
    """{scene: dict(A=(label, values), B=(label, values), engine=values, peers=values, floor={m: 10|A-B|})}"""
    out = {}
    for name in names:
        t0 = time.perf_counter()
        if name == "oscillator":
            v = osc_exact(OSC_T)[1]
            out[name] = dict(A=("closed form", {"object_final_velocity": v}), B=("closed form", {"object_final_velocity": v}),
                             engine=None, peers={"object_final_velocity": v}, floor={"object_final_velocity": 1e-15})
            continue
        ref_method = "rodas" if name == "compressible" else "dp5"
        ref_tol = dict(rtol=1e-12, atol=1e-15) if name == "compressible" else dict(rtol=1e-13, atol=1e-16)
        model = SCENES[name][2]
        if name == "compressible":
            a = engine_once(name, "rodas", rtol=1e-12, atol=1e-15)()
            la = "cushion rodas rtol 1e-12 atol 1e-15"
        else:
            a = engine_once(name, "dp5", rtol=1e-13, atol=1e-16)()
            la = "cushion dp5 rtol 1e-13 atol 1e-16"
        assert a.summary["status"] == "ok", (name, a.summary["status"])
        va = {m: a.summary[m] for m in MEASURES}
        va[TRAJECTORY] = engine_samples(name, ref_method, ref_tol)
        if model is None:
            b = engine_once(name, "rodas", rtol=1e-11, atol=1e-14)()
            assert b.summary["status"] == "ok", (name, b.summary["status"])
            vb = {m: b.summary[m] for m in MEASURES}
            vb[TRAJECTORY] = engine_samples(name, "rodas", dict(rtol=1e-11, atol=1e-14))
            lb = "cushion rodas rtol 1e-11 atol 1e-14"
            eng, peers = va, None
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                if name == "compressible":
                    cls, dt = model
                    scene = cls()
                    pieces, st = sts.solve(scene, "Radau", 1e-12, True, args.ref_budget, dead_time=dt, atol=1e-15)
                    lb = "SciPy Radau (exact Jacobian) rtol 1e-12 atol 1e-15"
                    assert st["status"] == "ok", st["status"]
                    vb = dict(sts.peaks(scene, pieces))
                    vb["object_final_velocity"] = st["y_end"][scene.i_vp]
                    vb["t_detect"] = st["t_detect"]
                    vb[TRAJECTORY] = ivp_samples(scene, pieces)
                    vb = {m: vb[m] for m in ALL_MEASURES}
                else:
                    r = scipy_ivp_once(name, "DOP853", 1e-13, 1e-16, args.ref_budget)
                    assert r["status"] == "ok", r["status"]
                    vb, lb = r["values"], "SciPy DOP853 (solve_ivp) rtol 1e-13 atol 1e-16"
            eng, peers = va, vb
        floor = {m: max(10 * abs(va[m] - vb[m]), 1e-15 * abs(va[m])) for m in MEASURES}
        floor[TRAJECTORY] = max(10 * disagreement(va, vb, TRAJECTORY), 1e-15)
        out[name] = dict(A=(la, va), B=(lb, vb), engine=eng, peers=peers, floor=floor)
        log(f"reference {name} ({time.perf_counter() - t0:.1f} s)")
    return out


def disagreement(va, vb, m):
    """|A - B| of one measure (for the trajectory, the largest over its samples)."""
    return trajectory_error(va[m], vb[m]) if m == TRAJECTORY else abs(va[m] - vb[m])


# ------------------------------------------------------------------------------ the study

def study(names, args, has_dop853):
    rows = []
    refs = references(names, args)
    log("\nreferences, two ways (A, B), and |A - B|:")
    for name in names:
        r = refs[name]
        for m in r["A"][1]:
            a, b = r["A"][1][m], r["B"][1][m]
            shown = (lambda v: f"{v:+.15g}") if m != TRAJECTORY else (lambda v: "(99 x 2 samples)".ljust(22))
            log(f"  {name:22s} {m:22s} A {shown(a)}  B {shown(b)}  |A-B| {disagreement(r['A'][1], r['B'][1], m):.2e}  "
                f"(A: {r['A'][0]}; B: {r['B'][0]})")

    q = args.quick
    dp5_rtols = [1e-3, 1e-5, 1e-7, 1e-9] if q else [10.0**-k for k in range(3, 13)]
    imp_rtols = [1e-3, 1e-5, 1e-7] if q else [10.0**-k for k in range(3, 11)]
    peer_rtols = [1e-3, 1e-5, 1e-7] if q else [10.0**-k for k in range(3, 11)]
    rk4_steps = [1e-4, 1e-5] if q else [1e-4, 3e-5, 1e-5, 3e-6, 1e-6]
    euler_steps = [1e-5, 1e-6] if q else [1e-5, 1e-6, 1e-7]
    ours = [("dp5", dp5_rtols, None), ("rodas", imp_rtols, None), ("auto", imp_rtols, None),
            ("rk4", None, rk4_steps), ("euler", None, euler_steps)]
    if has_dop853:
        ours.insert(1, ("dop853", dp5_rtols, None))
        ours.append(("dop853_no_ledger", dp5_rtols, None))
    ours.append(("dp5_no_ledger", dp5_rtols, None))
    ours.append(("dp5_no_tail", dp5_rtols, None))
    peers = ["RK45", "DOP853", "Radau", "LSODA", "hairer-dopri5", "hairer-dop853"]
    if isinstance(CYRK, cyrk_peer.Peer):
        peers += ["cyrk-DOP853", "cyrk-RK45"]

    def add(name, method, family, setting, res, ref, floor):
        for m in ALL_MEASURES:
            if name == "oscillator" and m != "object_final_velocity":
                continue
            v = res.get("values", {}).get(m) if res["status"] == "ok" else None
            if v is None:
                err = float("nan")
            elif m == TRAJECTORY:
                err, v = trajectory_error(v, ref[m]), None  # (the samples are not written)
            else:
                err = abs(v - ref[m])
            rows.append(dict(scene=name, method=method, family=family, setting=setting, error_measure=m,
                             status=res["status"], value=v if v is not None else float("nan"), error=err,
                             resolved=bool(math.isfinite(err) and err > floor[m]), floor=floor[m],
                             seconds=res.get("seconds", float("nan")), rhs_evals=res.get("rhs_evals", -1),
                             repeats=res.get("repeats", 0)))

    for name in names:
        ref, t_scene = refs[name], time.perf_counter()
        stiff = name == "compressible"
        points = []  # (method, family, setting, result), added once timed
        if name == "oscillator":
            settings = [(m, label, st) for m, rtols, steps in ours if m not in VARIANTS
                        for label, st in ([(f"rtol={sci(r)}", dict(rtol=r)) for r in rtols] if rtols
                                          else [(f"h={sci(h)}", dict(h=h)) for h in steps])]
            for (m, label), res in engine_oscillator(settings).items():
                add(name, m, "cushion", label, res, ref["peers"], ref["floor"])
        else:
            for method, rtols, steps in ours:
                rtols = rtol_grid(name, method, rtols) if rtols else rtols
                settings = ([(f"rtol={sci(r)}", dict(rtol=r, atol=r / 1000)) for r in rtols] if rtols
                            else [(f"h={sci(h)}", dict(h=h)) for h in steps])
                for label, st in settings:
                    if stiff and method in EXPLICIT_OURS:
                        res = dict(status="failed (explicit, not run)")
                    else:
                        res = engine_point(name, method, st, args)
                    points.append((method, "cushion", label, res))
        if name == "oscillator" or SCENES[name][2] is not None:
            for method in peers:
                dead = None
                for r in rtol_grid(name, method, peer_rtols):
                    label = f"rtol={sci(r)}"
                    if stiff and method in EXPLICIT_PEERS:
                        res = dict(status="failed (explicit, not run)")
                    elif dead:
                        res = dict(status=f"failed (not run: {dead} at a looser rtol)")
                    else:
                        res = peer_point(name, method, r, args)
                        if "time limit" in res["status"]:  # tighter settings would take longer still
                            dead = res["status"]
                    points.append((method, "peer", label, res))
                log(f"  {name} {method}: done")
        time_interleaved([res for *_, res in points], args)
        for method, family, label, res in points:
            add(name, method, family, label, res, ref["engine" if family == "cushion" else "peers"], ref["floor"])
        log(f"{name}: {time.perf_counter() - t_scene:.1f} s")
    return rows, refs


# ------------------------------------------------------------------------------ charts, table

STYLE = {  # ours strong and thick, peers muted and thin
    "dp5": dict(color="#1f4e9c", lw=2.6, marker="o", ms=4.5),
    "dop853": dict(color="#c0171d", lw=2.6, marker="D", ms=4.5),
    "dp5_no_ledger": dict(color="#1f4e9c", lw=1.6, marker="o", ms=3, ls=":", mfc="none"),
    "dop853_no_ledger": dict(color="#c0171d", lw=1.6, marker="D", ms=3, ls=":", mfc="none"),
    "dp5_no_tail": dict(color="#4f8fe0", lw=1.6, marker="o", ms=3, ls="--", mfc="none"),
    "rodas": dict(color="#1a7f37", lw=2.6, marker="s", ms=4.5),
    "auto": dict(color="#e07b00", lw=2.0, marker="^", ms=4.5, ls="--"),
    "rk4": dict(color="#7b2c9e", lw=2.0, marker="v", ms=4.5),
    "euler": dict(color="#6b3d1f", lw=2.0, marker="x", ms=5),
    "RK45": dict(color="#8c8c8c", lw=1.1, marker=".", ms=4),
    "DOP853": dict(color="#b0b0b0", lw=1.1, marker=".", ms=4, ls="--"),
    "Radau": dict(color="#9ab8d8", lw=1.1, marker=".", ms=4),
    "LSODA": dict(color="#e8b88a", lw=1.1, marker=".", ms=4),
    "hairer-dopri5": dict(color="#a0a0a0", lw=1.1, marker="+", ms=5, ls=":"),
    "hairer-dop853": dict(color="#c4c4c4", lw=1.1, marker="+", ms=5, ls="-."),
    "cyrk-DOP853": dict(color="#a8d5a0", lw=1.1, marker=".", ms=4),
    "cyrk-RK45": dict(color="#d3b5e0", lw=1.1, marker=".", ms=4, ls="--"),
}
LABEL = {
    "dp5": "cushion dp5", "dop853": "cushion dop853",
    "dp5_no_ledger": "cushion dp5, ledger off", "dop853_no_ledger": "cushion dop853, ledger off",
    "dp5_no_tail": "cushion dp5, ringing tail off",
    "rodas": "cushion rodas", "auto": "cushion auto",
    "rk4": "cushion rk4 (fixed h)", "euler": "cushion euler (fixed h)",
    "RK45": "SciPy RK45", "DOP853": "SciPy DOP853", "Radau": "SciPy Radau", "LSODA": "SciPy LSODA",
    "hairer-dopri5": "Hairer DOPRI5 (scipy ode)", "hairer-dop853": "Hairer DOP853 (scipy ode)",
    "cyrk-DOP853": "CyRK DOP853 + numba", "cyrk-RK45": "CyRK RK45 + numba",
}


CHARTS = {  # measure: (files by work measure, what the error is, its axis label)
    "object_final_velocity": ({"seconds": "work-precision-time.svg", "rhs_evals": "work-precision-evals.svg"},
                              "error in the object's final speed", "|final speed - reference| (m/s)"),
    TRAJECTORY: ({"seconds": "work-precision-trajectory.svg"},
                 "largest error of the tool's and the object's speeds at 99 fixed times",
                 "max |speed(t_k) - reference| (m/s)"),
}


def charts(df, names, outdir, measure="object_final_velocity"):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = df[(df.error_measure == measure) & (df.status == "ok")]
    names = [n for n in names if (d.scene == n).any()]
    if not names:
        return
    files, what, ylabel = CHARTS[measure]
    ncol = 4
    nrow = math.ceil(len(names) / ncol)
    for work, xlabel in (("seconds", "wall time per run (s)"), ("rhs_evals", "right-hand-side evaluations per run")):
        if work not in files:
            continue
        fname = files[work]
        fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.6 * nrow + 1.2), squeeze=False)
        handles = {}
        for ax, name in zip(axes.flat, names):
            s = d[d.scene == name]
            floor = s.floor.max() if len(s) else None
            for method in STYLE:
                if method == "dp5_no_tail" and measure != TRAJECTORY:
                    continue  # (the tail changes the trajectory, not the summary)
                mm = s[(s.method == method) & s.resolved]
                if mm.empty:
                    continue
                st = dict(STYLE[method])
                z = 3 if method in LABEL and not method[0].isupper() and "-" not in method else 2
                (h,) = ax.plot(mm[work], mm.error, label=LABEL[method], zorder=z, **st)
                handles[method] = h
            if floor and name != "oscillator":
                ax.axhline(floor, color="#d0d0d0", lw=0.8, ls="-", zorder=1)
                ax.text(0.02, floor, " reference floor", transform=ax.get_yaxis_transform(), fontsize=6.5,
                        color="#909090", va="bottom")
            ax.set_xscale("log")
            ax.set_yscale("log")
            title = name + (" (the integrator alone)" if name == "oscillator" else "")
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="major", color="#eeeeee", lw=0.6)
            ax.tick_params(labelsize=8)
            ax.set_xlabel(xlabel, fontsize=8)
            ax.set_ylabel((ylabel if name != "oscillator" else "|x'(T) - exact| (m/s)"), fontsize=8)
        for ax in list(axes.flat)[len(names):]:
            ax.set_visible(False)
        order = [m for m in STYLE if m in handles]
        fig.legend([handles[m] for m in order], [LABEL[m] for m in order], loc="lower center",
                   ncol=min(7, len(order)), fontsize=8, frameon=False)
        fig.suptitle(f"Work-precision: {what} against "
                     + ("wall time" if work == "seconds" else "right-hand-side evaluations")
                     + " (log-log; cushion strong, peers muted)", fontsize=11)
        fig.tight_layout(rect=(0, 0.07 if nrow > 1 else 0.12, 1, 0.96))
        path = os.path.join(outdir, fname)
        fig.savefig(path)
        plt.close(fig)
        log(f"wrote {os.path.relpath(path, ROOT)}")


def interpolate(df, scene, targets, measure="object_final_velocity", settled=False):
    """{method: {target: (seconds, evals)}} by log-log interpolation between settings, in the
    order of their evaluations: where the error first crosses the target, or with `settled`,
    where it crosses it for the last time (the work from which every costlier setting stays
    below the target; None if the costliest one is above it)."""
    out = {}
    d = df[(df.scene == scene) & (df.error_measure == measure) & (df.status == "ok") & df.resolved]
    for method, g in d.groupby("method", sort=False):
        g = g.sort_values("rhs_evals")
        e, s, n = np.log10(g.error.values), np.log10(g.seconds.values), np.log10(g.rhs_evals.values.astype(float))
        res = {}
        for tgt in targets:
            lt = math.log10(tgt)
            val = None
            pairs = range(len(e) - 1)
            for i in (reversed(pairs) if settled else pairs):
                if (e[i] - lt) * (e[i + 1] - lt) <= 0 and e[i] != e[i + 1]:
                    w = (lt - e[i]) / (e[i + 1] - e[i])
                    val = (10 ** (s[i] + w * (s[i + 1] - s[i])), 10 ** (n[i] + w * (n[i + 1] - n[i])))
                    break
            if settled and len(e) and e[-1] > lt:
                val = None
            res[tgt] = val
        out[method] = res
    return out


def machine_info():
    info = {"date": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            k, _, v = line.partition(":")
            if k.strip() in ("Model name", "CPU(s)", "Thread(s) per core", "Core(s) per socket"):
                info[k.strip()] = v.strip()
    except OSError:
        pass
    info["cores"] = os.cpu_count()
    info["load_average_at_start"] = os.getloadavg()
    git = lambda *a: subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    info["git_commit"] = git("rev-parse", "HEAD")
    # (porcelain lines begin with two status columns and a space; the helper strips the output's
    # ends, which would eat the first line's leading blank)
    porcelain = subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True).stdout
    info["git_dirty_files"] = [l[3:] for l in porcelain.splitlines() if l.strip()]
    import scipy
    info["versions"] = dict(python=platform.python_version(), numpy=np.__version__, scipy=scipy.__version__,
                            cushion=cushion.__version__)
    if isinstance(CYRK, cyrk_peer.Peer):
        info["versions"].update(CyRK=CYRK.version, numba=CYRK.numba)
    return info


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a smoke run: few settings, one repeat")
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--out", default=os.path.join(ROOT, "lab", "results"), help="folder of the CSV and JSON")
    ap.add_argument("--figures", default=os.path.join(ROOT, "docs", "figures"), help="folder of the charts")
    ap.add_argument("--budget", type=float, default=None, help="s per peer run before it counts as failed (30; quick 5)")
    ap.add_argument("--no-charts", action="store_true")
    args = ap.parse_args()
    args.budget = args.budget or (5.0 if args.quick else 30.0)
    args.ref_budget = 300.0
    # each setting's runs, ours and the peers' alike, timed over about `target` seconds in all
    # (at most `most` runs), in `rounds` interleaved rounds (`time_interleaved`); a peer run
    # over `peer_slow` seconds is timed once
    args.target, args.most, args.rounds = (0.05, 3, 1) if args.quick else (0.2, 2000, 5)
    args.peer_slow = 0.0 if args.quick else 1.0

    import pandas as pd
    t_start = time.perf_counter()
    cyrk_setup()  # before machine_info, which records CyRK's and numba's versions
    info = machine_info()
    has_dop853 = engine_has_dop853()
    log(f"cushion {cushion.__version__}, method dop853 {'available' if has_dop853 else 'not available (ConfigError)'}")
    log("CyRK: " + (f"{CYRK.version} with numba {CYRK.numba}" if isinstance(CYRK, cyrk_peer.Peer) else CYRK))
    rows, refs = study(args.scenes, args, has_dop853)
    df = pd.DataFrame(rows)
    os.makedirs(args.out, exist_ok=True)
    os.makedirs(args.figures, exist_ok=True)
    csv = os.path.join(args.out, "work_precision.csv")
    with open(csv, "w") as f:
        f.write(f"# lab/work_precision.py{' --quick' if args.quick else ''}: commit {info['git_commit'][:12]}, "
                f"{info['date']}, {info.get('Model name', '?')}, {info['cores']} cores; see work_precision.json\n")
        df.to_csv(f, index=False, float_format="%.10g")
    log(f"wrote {os.path.relpath(csv, ROOT)} ({len(df)} rows)")

    table, table_trajectory, table_settled = {}, {}, {}
    levels = tuple(10.0 ** -k for k in range(4, 10))
    for name in args.scenes:
        table[name] = {m: {f"{t:g}": v for t, v in r.items()} for m, r in interpolate(df, name, levels).items()}
        table_settled[name] = {m: {f"{t:g}": v for t, v in r.items()}
                               for m, r in interpolate(df, name, levels, settled=True).items()}
        table_trajectory[name] = {m: {f"{t:g}": v for t, v in r.items()}
                                  for m, r in interpolate(df, name, (1e-4, 1e-6), TRAJECTORY).items()}
    if "paper-hydraulic-dt70" in table:
        log("\npaper-hydraulic-dt70, object final speed: time and evaluations at an error of 1e-6 and 1e-9 "
            "(log-log interpolated)")
        for m, r in table["paper-hydraulic-dt70"].items():
            cells = ["-" if v is None else f"{v[0] * 1e6:10.0f} us {v[1]:9.0f} evals" for v in (r["1e-06"], r["1e-09"])]
            log(f"  {m:15s} {cells[0]:>30s} | {cells[1]:>30s}")
    for name in DENSE_GRID:
        if name not in table:
            continue
        log(f"\n{name}, object final speed: time per run where the error first crosses each level, and where it "
            "stays below it (log-log interpolated; the denser grid)")
        for m in DENSE_METHODS:
            if m not in table[name]:
                continue
            cells = [" / ".join("-" if v is None else f"{v[0] * 1e6:.0f}" for v in (table[name][m].get(k), table_settled[name][m].get(k)))
                     for k in table[name][m]]
            log(f"  {m:17s} " + "  ".join(f"{c:>11s}" for c in cells) + "  us (1e-4 ... 1e-9)")
    log("\nAgainst the targets (engine time over the compiled peer's: below 1 is ahead; first crossing, "
        "[where the error stays below]):")
    for line in target_lines(table, table_settled):
        log("  " + line)
    info.update(
        command=" ".join(["lab/work_precision.py"] + sys.argv[1:]),
        engine_has_dop853=has_dop853,
        cyrk=CYRK if isinstance(CYRK, str) else "CyRK nbsolve2_ivp with a numba cfunc right-hand side",
        numbalsoda="not used: does not build here (needs a Fortran compiler)",
        references={n: dict(A=r["A"][0], B=r["B"][0],
                            values_A={m: v for m, v in r["A"][1].items() if m != TRAJECTORY},
                            values_B={m: v for m, v in r["B"][1].items() if m != TRAJECTORY},
                            disagreement={m: disagreement(r["A"][1], r["B"][1], m) for m in r["A"][1]},
                            floor=r["floor"]) for n, r in refs.items()},
        at_error=table,
        at_error_trajectory=table_trajectory,
        at_error_settled=table_settled,
        wall_seconds=round(time.perf_counter() - t_start, 1),
        load_average_at_end=os.getloadavg(),
    )
    with open(os.path.join(args.out, "work_precision.json"), "w") as f:
        json.dump(info, f, indent=1, default=float)
    if not args.no_charts:
        for measure in CHARTS:
            charts(df, args.scenes, args.figures, measure)
    log(f"total {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
