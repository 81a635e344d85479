"""What the Python package adds to the engine's own time (a benchmark, not a test).

1. Per-run overhead of `cushion.simulate(..., trajectory=False)` over the in-process Rust run.
   The overhead is a fixed cost per call (arguments in, summary out), so it is measured on a
   run that costs almost nothing (`t_end` = 1 µs: one step), where it is not lost in the
   run's own time and this VM's drift: the Rust loop (`loop_scene N t_end=1e-6`, release) and
   the Python calls, best of ROUNDS each, for the four ways of giving a scene (a few
   overrides, a full dict of every key, a scene file, a `cushion.Scene` made once).
2. Sweep throughput of `cushion.sweep` against `cushion sweep` on sweeps/design-space.toml
   (16,384 runs), in memory and with `out`, alternated, best of ROUNDS.

    .venv/bin/python -m lab.python_overhead [ROUNDS]      # after bash scripts/test.sh or
                                                           # maturin develop --release
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cushion

ROOT = Path(__file__).resolve().parents[1]
TARGET = ROOT / os.environ.get("CARGO_TARGET_DIR", "target")
ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 7
TINY = {"t_end": 1e-6}


def rust_us(n: int = 200_000) -> float:
    out = subprocess.run(
        [str(TARGET / "release" / "loop_scene"), str(n), "t_end=1e-6"],
        capture_output=True, text=True, check=True,
    )
    return float(out.stdout.split()[0])


def best_us(call, n: int = 20_000) -> float:
    for _ in range(500):
        call()
    best = float("inf")
    for _ in range(ROUNDS):
        t = time.perf_counter()
        for _ in range(n):
            call()
        best = min(best, (time.perf_counter() - t) / n * 1e6)
    return best


def overhead() -> None:
    rust = min(rust_us() for _ in range(ROUNDS))
    full = {**cushion.load_scene(ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"), **TINY}
    scene_file = ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"
    prepared = cushion.Scene(scene_file, set=TINY)
    forms = {
        "set={a few keys}": lambda: cushion.simulate(set=TINY, trajectory=False),
        "a dict of every key": lambda: cushion.simulate(full, trajectory=False),
        "a scene file": lambda: cushion.simulate(scene_file, set=TINY, trajectory=False),
        "a cushion.Scene": lambda: cushion.simulate(prepared, trajectory=False),
    }
    print(f"fixed cost per call (t_end = 1 µs, one step): Rust alone {rust:.1f} µs, best of {ROUNDS}")
    print(f"{'scene given as':22} {'python µs':>10} {'overhead µs':>12}")
    for name, call in forms.items():
        us = best_us(call)
        print(f"{name:22} {us:10.1f} {us - rust:12.1f}")


def sweep_throughput() -> None:
    design = ROOT / "sweeps/design-space.toml"
    cli = TARGET / "release" / "cushion"
    times: dict[str, list[float]] = {"cli": [], "python": [], "python out=": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(max(3, ROUNDS // 2)):
            t = time.perf_counter()
            subprocess.run([str(cli), "sweep", str(design), "--out", f"{tmp}/cli{k}", "--quiet"], check=True)
            times["cli"].append(time.perf_counter() - t)
            t = time.perf_counter()
            frame = cushion.sweep(design, progress=False)
            times["python"].append(time.perf_counter() - t)
            t = time.perf_counter()
            cushion.sweep(design, progress=False, out=f"{tmp}/py{k}")
            times["python out="].append(time.perf_counter() - t)
    n = len(frame)
    print(f"\nsweeps/design-space.toml, {n} runs, every core; best / median of {len(times['cli'])}")
    for what, ts in times.items():
        print(f"{what:12} {min(ts):6.3f} s  {n / min(ts):8.0f} runs/s   median {statistics.median(ts):.3f} s")


if __name__ == "__main__":
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "cushion-studies", "--bin", "loop_scene"], cwd=ROOT, check=True)
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "cushion"], cwd=ROOT, check=True)
    overhead()
    sweep_throughput()
