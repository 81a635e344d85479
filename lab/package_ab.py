#!/usr/bin/env python3
"""Two builds of the Python package side by side: µs per `cushion.simulate(scene,
trajectory=False)` on the paper's dt70 scenes, the ledger on and off, in interleaved
processes (this VM's speed drifts, so neither build gets the quiet minutes alone).

    cp -r .venv/lib/python3.11/site-packages/cushion /tmp/plain   # keep the plain package
    bash scripts/build_pgo.sh --wheel                              # the profile-guided one into .venv
    .venv/bin/python -m lab.package_ab /tmp/plain [--alternations 10]

Prints the fastest and the median µs per call of each case and build (the one in `.venv` is
"installed"; the one in the folder given is put first on `PYTHONPATH`).
"""

import argparse
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DT70 = "sweeps/scenes/paper-hydraulic-dt70.toml"
CASES = [
    ("hydraulic dt70", DT70, {}),
    ("hydraulic dt70, ledger off", DT70, {"energy.ledger": False}),
    ("hydraulic dt70, ledger off, rtol 1e-9", DT70,
     {"energy.ledger": False, "solver.rtol": 1e-9, "solver.atol": 1e-12}),
    ("bistable dt70", "sweeps/scenes/paper-bistable-dt70.toml", {}),
]
CALLS, ROUNDS = 300, 3

# One process's work: the fastest of ROUNDS rounds of CALLS calls per case, a line each.
CHILD = f"""
import time, cushion
for name, path, settings in {CASES!r}:
    scene = cushion.Scene(path, set=settings)
    best = float("inf")
    for _ in range({ROUNDS}):
        t0 = time.perf_counter()
        for _ in range({CALLS}):
            cushion.simulate(scene, trajectory=False)
        best = min(best, time.perf_counter() - t0)
    print(name, best / {CALLS} * 1e6, sep="\\t")
"""


def one(pythonpath):
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    out = subprocess.run([sys.executable, "-c", CHILD], cwd=ROOT, env=env, check=True,
                         capture_output=True, text=True).stdout
    return {name: float(v) for name, v in (line.split("\t") for line in out.splitlines())}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("other", help="folder holding the other build's `cushion` package")
    ap.add_argument("--alternations", type=int, default=10)
    args = ap.parse_args()
    times = {"installed": [], "other": []}
    for _ in range(args.alternations):
        times["other"].append(one(os.path.abspath(args.other)))
        times["installed"].append(one(None))
    for name, _, _ in CASES:
        row = []
        for build in ("other", "installed"):
            v = [t[name] for t in times[build]]
            row.append(f"{build} {min(v):.1f} / {statistics.median(v):.1f}")
        print(f"{name}: " + " | ".join(row) + " µs (fastest / median)")


if __name__ == "__main__":
    main()
