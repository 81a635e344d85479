"""The speed of `cushion sensitivity` at the issue's size: D = 4 inputs, N = 2^14 base points,
second order (163,840 runs), every numeric output, 1,000 bootstrap resamples, 2 threads
(sweeps/sensitivity-bench.toml); and the analysis alone on synthetic columns of the same shape
(`cargo bench -p cushion-sensitivity --bench analyze`: 24 outputs, no runs).

    cargo build --release --locked --bin cushion
    .venv/bin/python -m lab.sensitivity_speed            # 3 rounds each, writes lab/results/sensitivity_speed.json
    .venv/bin/python -m lab.sensitivity_speed --tables   # docs/performance.md's table from the JSON

The command's rounds report its wall time, its CPU time (user + system, from the child's
rusage) and the analysis time it prints (`... outputs analysed in X s`)."""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
JSON = os.path.join(ROOT, "lab", "results", "sensitivity_speed.json")
DOC = os.path.join(ROOT, "docs", "performance.md")
BEGIN, END = "<!-- sensitivity-speed:begin -->", "<!-- sensitivity-speed:end -->"
BIN = os.path.join(ROOT, "target", "release", "cushion")
FILE = os.path.join(ROOT, "sweeps", "sensitivity-bench.toml")
OUT = os.path.join(ROOT, "target", "sensitivity-bench")


def command_round() -> dict:
    shutil.rmtree(OUT, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([BIN, "sensitivity", FILE, "--threads", "2", "--out", OUT],
                          capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"cushion sensitivity: exit {done.returncode}\n{done.stderr}")
    m = re.search(r"(\d+) runs \((\d+) not ok\), (\d+) outputs analysed in ([\d.]+) s", done.stdout)
    if not m:
        sys.exit(f"no 'analysed in' line in the command's output:\n{done.stdout}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall": wall, "cpu": cpu, "analysis": float(m[4]), "runs": int(m[1]),
            "not_ok": int(m[2]), "outputs": int(m[3])}


def design_space_round() -> float:
    """The design-space sweep's runs per second at the same time: this VM's speed moves by a
    fifth to a third from hour to hour, and docs/performance.md gives that sweep's figure."""
    out = os.path.join(ROOT, "target", "sensitivity-bench-ds")
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    subprocess.run([BIN, "sweep", os.path.join(ROOT, "sweeps", "design-space.toml"), "--threads", "2",
                    "--out", out, "--quiet"], check=True, cwd=ROOT)
    return 16384 / (time.perf_counter() - start)


def bench_rounds(rounds: int) -> list[float]:
    done = subprocess.run(["cargo", "bench", "--locked", "-p", "cushion-sensitivity", "--bench", "analyze",
                           "--", str(rounds)], capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, "RAYON_NUM_THREADS": "2"})
    if done.returncode != 0:
        sys.exit(f"cargo bench: exit {done.returncode}\n{done.stderr[-2000:]}")
    return [float(x) for x in re.findall(r"round \d+: ([\d.]+) s", done.stdout)]


def measure(rounds: int) -> dict:
    if not os.path.exists(BIN):
        sys.exit(f"{BIN} missing: cargo build --release --locked --bin cushion")
    command, design_space = [], []
    for _ in range(rounds):
        command.append(command_round())
        design_space.append(design_space_round())
    return {"rounds": rounds, "threads": 2, "command": command, "design_space_runs_per_second": design_space,
            "analysis_bench": bench_rounds(rounds)}


def fmt(xs: list[float]) -> str:
    return f"{min(xs):.2f} / {statistics.median(xs):.2f} s"


def table(r: dict) -> str:
    c = r["command"]
    first = c[0]
    return "\n".join([
        f"D = 4, N = 2^14, second order: {first['runs']:,} runs ({first['not_ok']} not ok), "
        f"every numeric output ({first['outputs']}), 1,000 resamples, 2 threads; fastest / median of "
        f"{r['rounds']} rounds:",
        "",
        "| | wall | CPU (user + system) |",
        "|---|---|---|",
        f"| `cushion sensitivity sweeps/sensitivity-bench.toml --threads 2` (runs, files, analysis) "
        f"| {fmt([x['wall'] for x in c])} | {fmt([x['cpu'] for x in c])} |",
        f"| its analysis (the time it prints: gathering the columns, estimating, bootstrap) "
        f"| {fmt([x['analysis'] for x in c])} | - |",
        f"| the analysis alone, 24 synthetic outputs (`cargo bench -p cushion-sensitivity --bench analyze`) "
        f"| {fmt(r['analysis_bench'])} | - |",
        "",
        f"In the same rounds the design-space sweep ran at {max(r['design_space_runs_per_second']):,.0f} runs/s "
        f"(fastest round; \"The design-space sweep\" above gives this machine's figure at a faster hour): "
        "the command's time scales with it.",
    ])


def write_doc(r: dict) -> None:
    text = open(DOC).read()
    if BEGIN not in text:
        sys.exit(f"{DOC}: no {BEGIN} marker to write the table at")
    block = (f"{BEGIN}\n<!-- generated by `.venv/bin/python -m lab.sensitivity_speed --tables` "
             f"from lab/results/sensitivity_speed.json -->\n{table(r)}\n{END}")
    text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: block, text, flags=re.S)
    open(DOC, "w").write(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tables", action="store_true", help="only regenerate the docs' table from the JSON")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    if not args.tables:
        with open(JSON, "w") as f:
            json.dump(measure(args.rounds), f, indent=1)
    r = json.load(open(JSON))
    write_doc(r)
    print(table(r))


if __name__ == "__main__":
    main()
