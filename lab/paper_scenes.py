"""One run of each paper scene, and the hydraulic one against plain SciPy.

    .venv/bin/python -m lab.paper_scenes            # needs valgrind and SciPy; a few minutes
    .venv/bin/python -m lab.paper_scenes --tables   # docs/performance.md's blocks from the results

The engine, in-process, at the scenes' defaults (rtol 1e-6, `auto`): µs per run, the fastest
and the median of interleaved rounds of `loop_scene N` over the five scenes (this VM's speed
moves by a third within minutes: interleaving shares the slow minutes out, and the fastest round
is the least disturbed); instructions per run (cachegrind: (200 runs - 0 runs) / 200, so
start-up drops out; they repeat to a few instructions whatever the machine does); evaluations
and steps (`cushion simulate --json`).

SciPy (`lab/scene_scipy.py`: the hydraulic dt70 scene in plain `solve_ivp`): RK45 at rtol 1e-3,
1e-4, 1e-6 and 1e-8 (atol = rtol / 1000), ms per run the fastest of 3 invocations of 5 runs, its
object final speed against the engine's at rtol 1e-12; and the steps of each `solve_ivp` method
at rtol 1e-6. The engine's side of that comparison comes from `lab.scene_tolerances` (its
results file), run in the same hour.

Writes lab/results/paper_scenes.json; the blocks `paper-scenes` and `against-scipy` of
docs/performance.md are drawn from it (here and by `python3 -m lab.make_docs`).
"""

import json
import os
import statistics
import subprocess
import time

from lab import study as lab
from lab.make_docs import PERFORMANCE
from lab.study import rt, sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "paper_scenes.json")
TOLERANCES = os.path.join(ROOT, "lab", "results", "scene_tolerances.json")
SCENES = ["paper-hydraulic-dt70", "paper-hydraulic-dt10", "paper-bistable-dt70", "paper-bistable-dt10",
          "paper-rigid"]
ROUNDS, RUNS = 25, 400
SCIPY_RTOLS = [1e-3, 1e-4, 1e-6, 1e-8]
SCIPY_METHODS = ["RK45", "DOP853", "Radau", "BDF", "LSODA"]


def path(scene):
    return os.path.join(ROOT, "sweeps", "scenes", f"{scene}.toml")


def instructions(scene):
    return lab.instructions_per_run([path(scene)], 200)


def simulate(scene, sets=()):
    return lab.simulate(path(scene), sets)


def wall_times():
    """µs per run of each scene in each of ROUNDS interleaved rounds."""
    times = {s: [] for s in SCENES}
    for _ in range(ROUNDS):
        for s in SCENES:
            out = subprocess.run([lab.binary("loop_scene"), str(RUNS), path(s)],
                                 capture_output=True, text=True, check=True).stdout
            times[s].append(float(out.split()[0]))
    return times


def scipy_runs(reference_speed):
    from lab import scene_scipy

    def timed(method, rtol):
        scene_scipy.RTOL, scene_scipy.ATOL = rtol, rtol / 1000
        scene_scipy.run(0.070, method)  # warm up
        best = []
        for _ in range(3):
            times = []
            for _ in range(5):
                t0 = time.perf_counter()
                _, y, nfev, _, steps = scene_scipy.run(0.070, method)
                times.append(time.perf_counter() - t0)
            best.append(statistics.median(times))
        return {"method": method, "rtol": rtol, "ms_per_run": 1e3 * min(best), "rhs_evals": int(nfev),
                "steps": int(sum(steps)), "speed_error": abs(float(y[3]) - reference_speed)}

    rk45 = [timed("RK45", r) for r in SCIPY_RTOLS]
    methods = [next(r for r in rk45 if r["rtol"] == 1e-6)] + [timed(m, 1e-6) for m in SCIPY_METHODS[1:]]
    return rk45, methods


def measure(args=None):
    lab.release("loop_scene", package="cushion-studies")
    lab.release("cushion")
    times = wall_times()
    scenes = []
    for s in SCENES:
        stats = simulate(s)["stats"]
        scenes.append({"scene": s, "us_fastest": min(times[s]), "us_median": statistics.median(times[s]),
                       "instructions_per_run": instructions(s), "rhs_evals": stats["rhs_evals"],
                       "steps": stats["steps"]})
    reference = simulate("paper-hydraulic-dt70", ["solver.rtol=1e-12", "solver.atol=1e-15"])
    rk45, methods = scipy_runs(reference["object_final_velocity"])
    return {"rounds": ROUNDS, "runs_per_round": RUNS, "scenes": scenes,
            "reference_object_final_velocity": reference["object_final_velocity"],
            "scipy_rk45": rk45, "scipy_methods": methods}


def scenes_block(study):
    out = [f"| scene | µs/run, fastest / median of {study['rounds']} rounds of {study['runs_per_round']} | "
           "instructions/run | rhs evaluations | steps |", "|---|---|---|---|---|"]
    for r in study["scenes"]:
        out.append(f"| {r['scene']} | {r['us_fastest']:.1f} / {r['us_median']:.1f} | {r['instructions_per_run']:,} | "
                   f"{r['rhs_evals']:,} | {r['steps']:,} |")
    scipy = next(r for r in study["scipy_rk45"] if r["rtol"] == 1e-6)
    dt70 = next(r for r in study["scenes"] if r["scene"] == "paper-hydraulic-dt70")
    out.append(f"| SciPy RK45, paper-hydraulic-dt70 (`lab/scene_scipy.py`, fastest of 3) | "
               f"{1e3 * scipy['ms_per_run']:,.0f} | | {scipy['rhs_evals']:,} | {scipy['steps']:,} |")
    fast = [r["us_fastest"] for r in study["scenes"]]
    out += ["", f"The paper scenes take {min(fast):.0f}-{max(fast):.0f} µs a run; on the hydraulic scene SciPy "
            f"takes {1e3 * scipy['ms_per_run'] / dt70['us_fastest']:.0f} times the engine's time for "
            f"{scipy['rhs_evals'] / dt70['rhs_evals']:.1f} times its evaluations."]
    return out


def scipy_block(study):
    with open(TOLERANCES) as f:
        engine = {r["rtol"]: r for r in json.load(f)["scenes"]["hydraulic dt70"]["rows"]}
    out = ["| rtol | SciPy RK45: rhs evaluations, ms/run, speed error (m/s) | "
           "cushion: rhs evaluations, µs/run, speed error (m/s) |", "|---|---|---|"]
    error_ratio, time_ratio = [], []
    for r in study["scipy_rk45"]:
        e = engine[r["rtol"]]
        out.append(f"| {rt(r['rtol'])} | {r['rhs_evals']:,}, {r['ms_per_run']:.1f}, {sci(r['speed_error'])} | "
                   f"{e['rhs_evals']:,}, {e['us_per_run']:.0f}, {sci(e['object_final_velocity'])} |")
        error_ratio.append(r["speed_error"] / e["object_final_velocity"])
        time_ratio.append(1e3 * r["ms_per_run"] / e["us_per_run"])
    steps = ", ".join(f"{r['steps']:,} ({r['method']})" for r in study["scipy_methods"])
    engine_steps = engine[1e-6]["steps"]
    out += ["", f"At the same tolerance SciPy's error is {min(error_ratio):.1f} to {max(error_ratio):.0f} times "
            f"the engine's and its time {min(time_ratio):.0f} to {max(time_ratio):.0f} times. With each of "
            f"SciPy's methods (rtol 1e-6) the scene takes {steps} steps, the engine {engine_steps:,}."]
    return out


def blocks(study):
    source = "lab/results/paper_scenes.json"
    return [(PERFORMANCE, "paper-scenes", "\n".join(scenes_block(study)), source),
            (PERFORMANCE, "against-scipy", "\n".join(scipy_block(study)),
             source + " and lab/results/scene_tolerances.json")]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
