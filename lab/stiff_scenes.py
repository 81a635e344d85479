"""The hydraulic paper scene (dead time 70 ms) made stiff three ways, under each method of the
engine and of SciPy, at rtol 1e-6 and 1e-7 (atol = rtol / 1000):

- steel end-stops (`stops.stiffness` 1e11), a steel contact (`object.contact_stiffness` 1e10),
  a compressible liquid (`hydraulic.bulk_modulus` 1.5e9, where `dp5` and `dop853` stop at their
  step limit and are left out);
- the engine in-process: instructions per run (cachegrind on `loop_scene`: (3 runs - 0 runs) /
  3), µs per run (the median of 5 rounds of `loop_scene 20`), and the run's counts (`cushion
  simulate --json`): evaluations, Jacobians, LU factorizations, method switches;
- SciPy (`lab/stiff_scenes_scipy.py`, each run a child process with a time budget): Radau, BDF,
  LSODA and RK45 on the steel stops, LSODA, BDF and Radau on the compressible liquid, with
  finite-difference Jacobians as a SciPy user gets them.

    .venv/bin/python -m lab.stiff_scenes            # a few minutes after the release build
    .venv/bin/python -m lab.stiff_scenes --tables   # docs/performance.md's blocks from the results

Writes lab/results/stiff_scenes.json; the blocks `stiff-scenes` and `stiff-scenes-scipy` of
docs/performance.md are drawn from it (here and by `python3 -m lab.make_docs`).
"""

import os
import statistics
import subprocess

from lab import study as lab
from lab.make_docs import PERFORMANCE
from lab.study import rt

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "stiff_scenes.json")
SCENE = os.path.join(ROOT, "sweeps", "scenes", "paper-hydraulic-dt70.toml")
VARIANTS = {
    "steel stops (`stops.stiffness` 1e11)": "stops.stiffness=1e11",
    "steel contact (`object.contact_stiffness` 1e10)": "object.contact_stiffness=1e10",
    "compressible liquid (`bulk_modulus` 1.5e9)": "hydraulic.bulk_modulus=1.5e9",
}
METHODS = ["dp5", "dop853", "rodas", "auto"]
RTOLS = [1e-6, 1e-7]
SCIPY = {"steel": ["RK45", "LSODA", "Radau", "BDF"], "compressible": ["LSODA", "BDF", "Radau"]}


def sets(variant, method, rtol):
    return [VARIANTS[variant], f"solver.method={method}", f"solver.rtol={rtol:g}", f"solver.atol={rtol / 1000:g}"]


def engine_row(variant, method, rtol):
    args = sets(variant, method, rtol)
    run = lab.simulate(SCENE, args)
    st = run["stats"]
    times = [float(subprocess.run([lab.binary("loop_scene"), "20", SCENE, *args], capture_output=True,
                                  text=True, check=True).stdout.split()[0]) for _ in range(5)]
    return {"variant": variant, "method": method, "rtol": rtol, "status": run["status"],
            "instructions_per_run": lab.instructions_per_run([SCENE, *args], 3), "us_per_run": statistics.median(times),
            "rhs_evals": st["rhs_evals"], "jacobians": st["jacobians"], "lus": st["lu_decompositions"],
            "switches": st["method_switches"]}


def measure(args=None):
    from lab import stiff_scenes_scipy as sp

    lab.release("loop_scene", package="cushion-studies")
    lab.release("cushion")
    engine = [engine_row(v, m, r) for v in VARIANTS for m in METHODS for r in RTOLS
              if not (v.startswith("compressible") and m in ("dp5", "dop853"))]
    scipy = []
    for scene, methods in SCIPY.items():
        for method in methods:
            for rtol in RTOLS:
                st = sp.run_in_child(scene, method, rtol, False, 60.0, 120.0)
                scipy.append({"scene": scene, "method": method, "rtol": rtol, "status": st["status"],
                              "seconds": st["seconds"], "f_calls": st.get("f_calls"), "njev": st.get("njev"),
                              "nlu": st.get("nlu")})
    return {"engine": engine, "scipy": scipy}


def pair(rows, key, f):
    return " / ".join(f(r[key]) for r in rows)


def engine_table(study):
    out = ["| scene | method | rtol | instructions/run | µs/run | rhs evals | Jacobians | LUs | switches |",
           "|---|---|---|---|---|---|---|---|---|"]
    for variant in VARIANTS:
        first = True
        for method in METHODS:
            rows = [r for r in study["engine"] if r["variant"] == variant and r["method"] == method]
            if not rows:
                continue
            million = lambda x: f"{x / 1e6:.3g} M"
            out.append(f"| {variant if first else ''} | {method} | {pair(rows, 'rtol', rt)} | "
                       f"{pair(rows, 'instructions_per_run', million)} | {pair(rows, 'us_per_run', lambda x: f'{x:,.0f}')} | "
                       f"{pair(rows, 'rhs_evals', lambda x: f'{x:,}')} | {pair(rows, 'jacobians', lambda x: f'{x:,}')} | "
                       f"{pair(rows, 'lus', lambda x: f'{x:,}')} | {pair(rows, 'switches', str)} |")
            first = False
    return out


def scipy_table(study):
    out = ["| scene | method | rtol | seconds/run | calls | Jacobians | LUs |", "|---|---|---|---|---|---|---|"]
    for scene, methods in SCIPY.items():
        first = True
        for method in methods:
            rows = [r for r in study["scipy"] if r["scene"] == scene and r["method"] == method]
            ok = all(r["status"] == "ok" for r in rows)
            num = lambda x: "" if x is None else f"{x:,}"
            explicit = method == "RK45"
            out.append(f"| {scene if first else ''} | {method} | {pair(rows, 'rtol', rt)} | "
                       + (f"{pair(rows, 'seconds', lambda x: f'{x:.3g}')} | {pair(rows, 'f_calls', num)} | "
                          f"{'' if explicit else pair(rows, 'njev', num)} | {'' if explicit else pair(rows, 'nlu', num)} |"
                          if ok else f"{pair(rows, 'status', str)} | | | |"))
            first = False
    return out


def blocks(study):
    return [(PERFORMANCE, "stiff-scenes", "\n".join(engine_table(study))),
            (PERFORMANCE, "stiff-scenes-scipy", "\n".join(scipy_table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
