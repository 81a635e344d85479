"""What the Python package adds to the engine's own time (a benchmark, not a test).

1. Per-run overhead of `cushion.simulate(..., trajectory=False)` over the in-process Rust run.
   The overhead is a fixed cost per call (arguments in, summary out), so it is measured on a
   run that costs almost nothing (`t_end` = 1 µs: one step), where it is not lost in the
   run's own time and this VM's drift: the Rust loop (`loop_scene N t_end=1e-6`, release) and
   the Python calls, best of ROUNDS each, for the four ways of giving a scene (a few
   overrides, a full dict of every key, a scene file, a `cushion.Scene` made once).
2. Sweep throughput of `cushion.sweep` against `cushion sweep` on sweeps/design-space.toml
   (16,384 runs), in memory and with `out`, alternated, best of ROUNDS.

    .venv/bin/python -m lab.python_overhead [--rounds N]  # with the release wheel installed
                                                           # (bash lab/setup_venv.sh)
    .venv/bin/python -m lab.python_overhead --tables       # docs/performance.md's blocks

Writes lab/results/python_overhead.json; the blocks `python-overhead` and `python-sweep` of
docs/performance.md are drawn from it (here and by `python3 -m lab.make_docs`).
"""

from __future__ import annotations

import subprocess
import tempfile
import time
from pathlib import Path

from lab import study as lab
from lab.make_docs import PERFORMANCE

ROOT = Path(__file__).resolve().parents[1]
RESULTS = str(ROOT / "lab" / "results" / "python_overhead.json")
ROUNDS = 7
TINY = {"t_end": 1e-6}


def rust_us(n: int = 200_000) -> float:
    out = subprocess.run(
        [lab.binary("loop_scene"), str(n), "t_end=1e-6"],
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


def overhead() -> dict:
    import cushion

    rust = min(rust_us() for _ in range(ROUNDS))
    full = {**cushion.load_scene(ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"), **TINY}
    scene_file = ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"
    prepared = cushion.Scene(scene_file, set=TINY)
    forms = {
        "`set={...}` with a few keys (the common case)": lambda: cushion.simulate(set=TINY, trajectory=False),
        f"a dict of every key ({len(full)}, `cushion.load_scene(...)`)": lambda: cushion.simulate(full, trajectory=False),
        "a scene file path (read and parsed on every call)":
            lambda: cushion.simulate(scene_file, set=TINY, trajectory=False),
        "a `cushion.Scene` made once from the file": lambda: cushion.simulate(prepared, trajectory=False),
    }
    return {"rust_us": rust, "forms": {name: best_us(call) for name, call in forms.items()}}


def sweep_throughput() -> dict:
    import cushion

    design = ROOT / "sweeps/design-space.toml"
    cli = lab.binary("cushion")
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
    return {"runs": len(frame), "seconds": {k: sorted(v) for k, v in times.items()}}


def tables(study: dict) -> tuple[list[str], list[str]]:
    rust = study["overhead"]["rust_us"]
    first = ["| scene given as | Python µs per call | Rust alone µs | overhead µs |", "|---|---|---|---|"]
    for name, us in study["overhead"]["forms"].items():
        first.append(f"| {name} | {us:.1f} | {rust:.1f} | {us - rust:.1f} |")
    first += ["", f"Best of {study['rounds']} rounds."]
    sweep = study["sweep"]
    label = {"cli": "`cushion sweep ... --out DIR` (the command)", "python": "`cushion.sweep(path)` (in memory)",
             "python out=": "`cushion.sweep(path, out=DIR)` (every file the command writes)"}
    second = ["| how | seconds | runs/s |", "|---|---|---|"]
    for k, ts in sweep["seconds"].items():
        second.append(f"| {label[k]} | {ts[0]:.3f} | {sweep['runs'] / ts[0]:,.0f} |")
    second += ["", f"Best of {len(sweep['seconds']['cli'])} rounds, alternating."]
    return first, second


def measure(args) -> dict:
    global ROUNDS
    ROUNDS = args.rounds
    lab.release("loop_scene", package="cushion-studies")
    lab.release("cushion")
    return {"rounds": ROUNDS, "overhead": overhead(), "sweep": sweep_throughput()}


def blocks(study: dict):
    first, second = tables(study)
    return [(PERFORMANCE, "python-overhead", "\n".join(first)), (PERFORMANCE, "python-sweep", "\n".join(second))]


def main() -> None:
    lab.main(__doc__, RESULTS, measure, blocks,
             options=lambda ap: ap.add_argument("--rounds", type=int, default=ROUNDS))


if __name__ == "__main__":
    main()
