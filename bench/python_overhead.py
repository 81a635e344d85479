"""What the Python package adds to the engine's own time (a benchmark, not a test).

1. Per-run overhead of `cushion.simulate` over the in-process Rust run, for each paper scene:
   rounds alternate `loop_scene N SCENE` (the Rust loop, release build) with the same number of
   `cushion.simulate(SCENE_DICT, trajectory=False)` calls in this process, and the overhead of
   a round is the difference of the two per-run times; the fastest and median rounds are
   printed (this VM's speed moves within minutes, so rounds interleave).
2. Sweep throughput of `cushion.sweep` against `cushion sweep` on sweeps/design-space.toml
   (16,384 runs), in memory and with `out`, alternated, best of ROUNDS.

    .venv/bin/python bench/python_overhead.py [ROUNDS]      # after bash scripts/test.sh or
                                                           # maturin develop --release
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cushion

ROOT = Path(__file__).resolve().parents[1]
ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 7
N = 2000


def rust_us(scene: Path) -> float:
    out = subprocess.run(
        [str(ROOT / "target/release/examples/loop_scene"), str(N), str(scene)],
        capture_output=True, text=True, check=True,
    )
    return float(out.stdout.split()[0])


def python_us(scene: dict) -> float:
    t = time.perf_counter()
    for _ in range(N):
        cushion.simulate(scene, trajectory=False)
    return (time.perf_counter() - t) / N * 1e6


def overhead() -> None:
    print(f"per-run overhead of cushion.simulate(trajectory=False), {ROUNDS} rounds of {N} runs")
    print(f"{'scene':24} {'rust µs':>9} {'python µs':>10} {'overhead µs (min / median)':>28}")
    for scene in sorted((ROOT / "sweeps/scenes").glob("paper-*.toml")):
        as_dict = cushion.load_scene(scene)
        python_us(as_dict)  # warm up
        rows = [(rust_us(scene), python_us(as_dict)) for _ in range(ROUNDS)]
        diffs = sorted(p - r for r, p in rows)
        print(
            f"{scene.stem:24} {min(r for r, _ in rows):9.1f} {min(p for _, p in rows):10.1f}"
            f" {diffs[0]:13.1f} / {statistics.median(diffs):.1f}"
        )


def sweep_throughput() -> None:
    design = ROOT / "sweeps/design-space.toml"
    cli = ROOT / "target/release/cushion"
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
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "cushion-model", "--example", "loop_scene"], cwd=ROOT, check=True)
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "cushion"], cwd=ROOT, check=True)
    overhead()
    sweep_throughput()
