"""Accuracy over every option: a 3,000-run Latin hypercube over module, dead time, gas pressure,
orifice, object mass, dry friction, plane friction, robot start, cavitation, brake and rtol
(1e-4, 1e-6, 1e-8; atol 1e-9 as in the scenes), against the same runs at rtol 1e-11, atol 1e-14
(the reference sweep lists 1e-11 three times for the rtol axis, so that the hypercube draws the
same points). Per rtol, the median, 99th percentile and largest error of the object's final
speed (m/s) and of the robot impulse (N s), with the worst run. A benchmark, not a test.

    python3 -m lab.options_accuracy            # about a minute on 2 cores after the release build
    python3 -m lab.options_accuracy --tables   # docs/accuracy.md's block from the results

Writes lab/results/options_accuracy.json; the block `options-accuracy` of docs/accuracy.md is
drawn from it (here and by `python3 -m lab.make_docs`).
"""

import csv
import os
import subprocess
import sys
import tempfile

from lab import study as lab
from lab.study import rt, sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = os.path.join(ROOT, os.environ.get("CARGO_TARGET_DIR", "target"), "release", "cushion")
RESULTS = os.path.join(ROOT, "lab", "results", "options_accuracy.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
MEASURES = {"object_final_velocity": "object final speed (m/s)", "robot_impulse": "robot impulse (N s)"}
AXES = """
[sampling]
mode = "lhs"
samples = 3000
seed = 11
[[axis]]
key = "module"
values = ["hydraulic", "bistable", "rigid"]
[[axis]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[axis]]
key = "hydraulic.gas_pressure"
range = [300.0, 1e5]
scale = "log"
[[axis]]
key = "hydraulic.orifice_radius"
range = [0.002, 0.012]
[[axis]]
key = "object.mass"
range = [0.05, 1.0]
[[axis]]
key = "tool.dry_friction"
values = [0.0, 0.0, 0.3]
[[axis]]
key = "object.plane_friction"
values = [0.0, 0.0, 0.4]
[[axis]]
key = "robot.start"
values = ["cruising", "rest"]
[[axis]]
key = "hydraulic.cavitation"
values = [false, false, true]
[[axis]]
key = "robot.brake_deceleration"
range = [5.0, 30.0]
[[axis]]
key = "solver.rtol"
"""


def summary(tmp, name, rtols, set_lines):
    text = (f'name = "options"\nscene = "{ROOT}/sweeps/scenes/paper-hydraulic-dt70.toml"\n{set_lines}\n'
            f"{AXES}values = {rtols}\n")
    path, out = os.path.join(tmp, f"{name}.toml"), os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    subprocess.run([CLI, "sweep", path, "--out", out, "--quiet"], check=True)
    with open(os.path.join(out, "summary.csv")) as f:
        return list(csv.DictReader(f))


def measure(args=None):
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "cushion"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory() as tmp:
        run = summary(tmp, "run", "[1e-6, 1e-8, 1e-4]", "")
        ref = summary(tmp, "reference", "[1e-11, 1e-11, 1e-11]", '[set]\n"solver.atol" = 1e-14')
    axes = [k for k in run[0] if k not in ("run", "solver.rtol") and k in ref[0]][:10]
    if not all(r[k] == x[k] for r, x in zip(ref, run) for k in axes):
        sys.exit("options_accuracy.py: the two sweeps drew different points")
    errs = {}
    for r, x in zip(ref, run):
        for k in MEASURES:
            errs.setdefault((float(x["solver.rtol"]), k), []).append((abs(float(r[k]) - float(x[k])), int(x["run"])))
    rows = []
    for (rtol, k), e in sorted(errs.items(), key=lambda kv: (-kv[0][0], kv[0][1])):
        e.sort()
        n = len(e)
        rows.append({"rtol": rtol, "measure": k, "runs": n, "median": e[n // 2][0], "p99": e[int(0.99 * n)][0],
                     "largest": e[-1][0], "largest_run": e[-1][1]})
    return {"runs": len(run), "rows": rows}


def table(study):
    out = ["| rtol | " + " | ".join(f"{label}: median / p99 / largest (run)" for label in MEASURES.values()) + " |",
           "|---|---|---|"]
    rtols = sorted({r["rtol"] for r in study["rows"]}, reverse=True)
    for rtol in rtols:
        cells = []
        for k in MEASURES:
            r = next(r for r in study["rows"] if r["rtol"] == rtol and r["measure"] == k)
            cells.append(f"{sci(r['median'])} / {sci(r['p99'])} / {sci(r['largest'])} ({r['largest_run']})")
        out.append(f"| {rt(rtol)} | " + " | ".join(cells) + " |")
    return out


def blocks(study):
    return [(ACCURACY, "options-accuracy", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
