#!/usr/bin/env python3
"""cushion sweep against SciPy solve_ivp RK45 on a sample of the design-space runs.

Takes every k-th hydraulic run of sweeps/design-space.toml (the SciPy model in
lab/scene_scipy.py has the hydraulic module only), times those runs in SciPy (RK45, rtol 1e-6,
atol 1e-9, the same physics) and in `cushion sweep` (the same runs as a zip sweep, 1 thread,
release build), and prints the time per run of each and their ratio, plus how far the two
agree on the object's final velocity.

    bash lab/setup_venv.sh && cargo build --release
    .venv/bin/python -m lab.sweep_scipy [--sample 100]
"""

import argparse
import warnings
import csv
import json
import math
import os
import shutil
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
from lab import scene_scipy as sc  # noqa: E402  (the SciPy scene model, reused as is)

AXES = ["robot.dead_time", "hydraulic.gas_pressure", "hydraulic.orifice_radius", "object.mass"]


def design_runs(binary, workdir):
    """The design-space runs' axis values, from a cushion sweep of the file (hydraulic ones)."""
    out = os.path.join(workdir, "ds")
    # The axis values do not depend on the model; 1/16 of the sweep is plenty to sample from.
    subprocess.run([binary, "sweep", os.path.join(ROOT, "sweeps/design-space.toml"), "--out", out,
                    "--shard", "1/16", "--quiet"], check=True)
    with open(os.path.join(out, "summary.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["module"] == "hydraulic"]
    return rows


def cushion_sweep(binary, tmp, sample, rtol, atol=None, repeat=3):
    """The design runs `sample` as one zip sweep of the hydraulic module at `rtol` (and `atol`,
    else the scene's), 1 thread, the whole command timed `repeat` times: (best wall seconds,
    summary rows)."""
    lines = ['name = "sample"',
             f'scene = "{os.path.join(ROOT, "sweeps/scenes/paper-hydraulic-dt70.toml")}"',
             '[set]', f'"solver.rtol" = {rtol!r}', '"module" = "hydraulic"']
    if atol is not None:
        lines.append(f'"solver.atol" = {atol!r}')
    lines += ['[sampling]', 'mode = "zip"']
    for key in AXES:
        vals = ", ".join(repr(float(r[key])) for r in sample)
        lines += ["[[axis]]", f'key = "{key}"', f"values = [{vals}]"]
    path = os.path.join(tmp, f"sample-{rtol:g}.toml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    out = os.path.join(tmp, f"rust-{rtol:g}")
    best = math.inf
    for _ in range(repeat):
        shutil.rmtree(out, ignore_errors=True)
        subprocess.run([binary, "sweep", path, "--out", out, "--threads", "1", "--quiet"], check=True)
        with open(os.path.join(out, "provenance.json")) as f:
            best = min(best, json.load(f)["wall_seconds"])
    with open(os.path.join(out, "summary.csv")) as f:
        return best, list(csv.DictReader(f))


def scipy_run(row):
    sc.P10 = float(row["hydraulic.gas_pressure"])
    r_o = float(row["hydraulic.orifice_radius"])
    sc.R_O, sc.A_O = r_o, math.pi * r_o**2
    sc.M_P = float(row["object.mass"])
    t0 = time.perf_counter()
    _, y, nfev, _, _ = sc.run(float(row["robot.dead_time"]))
    return time.perf_counter() - t0, y[3], nfev


def main():
    # The SciPy model's trial steps may overshoot the gas volume (NaN, then rejected): quiet.
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sample", type=int, default=100, help="hydraulic runs to time")
    ap.add_argument("--binary", default=os.path.join(ROOT, "target/release/cushion"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = design_runs(args.binary, tmp)
        step = max(1, len(rows) // args.sample)
        sample = rows[::step][: args.sample]

        # Rust: the same runs as one zip sweep, 1 thread.
        best, rust_rows = cushion_sweep(args.binary, tmp, sample, 1e-6)

        scipy_run(sample[0])  # warm up
        total, diffs, nfevs, rust_evals = 0.0, [], [], []
        for r, rr in zip(sample, rust_rows):
            dt, v, nfev = scipy_run(r)
            total += dt
            nfevs.append(nfev)
            rust_evals.append(int(rr["stats_rhs_evals"]))
            vr = float(rr["object_final_velocity"])
            diffs.append(abs(v - vr) / max(abs(vr), 1e-12))
        n = len(sample)
        diffs.sort()
        print(f"{n} hydraulic runs of sweeps/design-space.toml (rtol 1e-6, atol 1e-9), 1 thread")
        print(f"SciPy solve_ivp RK45: {total / n * 1e3:.2f} ms/run, median {sorted(nfevs)[n // 2]} rhs evaluations")
        print(f"cushion sweep:        {best / n * 1e3:.3f} ms/run (whole command, best of 3), "
              f"median {sorted(rust_evals)[n // 2]} rhs evaluations")
        print(f"ratio SciPy / cushion: {total / best:.0f}x")
        print(f"object final velocity, relative difference: median {diffs[n // 2]:.1e}, max {diffs[-1]:.1e}")


if __name__ == "__main__":
    main()
