"""The design-space sweep's throughput and memory (a benchmark, not a test):

- runs per second of `cushion sweep sweeps/design-space.toml` (16,384 runs, rtol 1e-6) with 1
  and 2 threads, the best of REPEAT rounds (default 3), alternating, so that a busy machine
  disturbs both alike;
- peak resident memory (`/usr/bin/time -v`) for 10^4 and 10^5 runs (the same axes, Latin
  hypercube, since Sobol stops at 65,536 points), which stays flat: rows stream to disk chunk by
  chunk.

    .venv/bin/python -m lab.sweep_bench [--repeat N]    # about a minute after the release build
    .venv/bin/python -m lab.sweep_bench --tables        # docs/performance.md's block from the results
    CUSHION_BIN=target/pgo/release/cushion .venv/bin/python -m lab.sweep_bench --out FILE
                                                        # another build (the profile-guided one)

Writes lab/results/sweep_bench.json (or `--out`); the block `design-space-sweep` of
docs/performance.md is drawn from it (here and by `python3 -m lab.make_docs`).
"""

import json
import os
import re
import subprocess
import sys
import tempfile

from lab import study as lab
from lab.make_docs import PERFORMANCE

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "sweep_bench.json")
SWEEP = os.path.join(ROOT, "sweeps", "design-space.toml")


def run(cli, sweep, out, threads):
    """One sweep under GNU time: runs, wall (the command's own), CPU and peak memory."""
    timed = subprocess.run(["/usr/bin/time", "-v", cli, "sweep", sweep, "--out", out, "--threads", str(threads),
                            "--quiet"], capture_output=True, text=True, check=True).stderr
    fields = dict(line.strip().rpartition(": ")[::2] for line in timed.splitlines() if ": " in line)
    with open(os.path.join(out, "provenance.json")) as f:
        prov = json.load(f)
    return {"runs": prov["runs_in_output"], "wall_seconds": prov["wall_seconds"],
            "cpu_seconds": float(fields["User time (seconds)"]) + float(fields["System time (seconds)"]),
            "peak_rss_mib": int(fields["Maximum resident set size (kbytes)"]) / 1024}


def memory_sweep(tmp, n):
    text = open(SWEEP).read()
    text = re.sub(r'^mode = "sobol"', 'mode = "lhs"', text, flags=re.M)
    text = re.sub(r"^samples = .*", f"samples = {n}", text, flags=re.M)
    text = text.replace('scene = "', f'scene = "{ROOT}/sweeps/', 1)
    path = os.path.join(tmp, f"mem-{n}.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def measure(cli, repeat):
    import pandas as pd

    rounds = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeat):
            for threads in (1, 2):
                rounds[threads].append(run(cli, SWEEP, os.path.join(tmp, f"t{threads}"), threads))
        evals = pd.read_parquet(os.path.join(tmp, "t2", "summary.parquet"))["stats_rhs_evals"].mean()
        memory = {n: run(cli, memory_sweep(tmp, n), os.path.join(tmp, f"mem-{n}"), 2) for n in (10_000, 100_000)}
    best = {t: min(r, key=lambda x: x["wall_seconds"]) for t, r in rounds.items()}
    return {"binary": os.path.relpath(cli, ROOT), "repeat": repeat, "threads_1": best[1], "threads_2": best[2],
            "rounds_1": rounds[1], "rounds_2": rounds[2], "memory_10000": memory[10_000],
            "memory_100000": memory[100_000], "rhs_evals_mean": float(evals)}


def table(study):
    one, two = study["threads_1"], study["threads_2"]
    m4, m5 = study["memory_10000"], study["memory_100000"]
    rate = lambda r: r["runs"] / r["wall_seconds"]
    return ["| | |", "|---|---|",
            f"| 1 thread | {rate(one):,.0f} runs/s ({one['wall_seconds']:.2f} s, CPU {one['cpu_seconds']:.2f} s) |",
            f"| 2 threads | {rate(two):,.0f} runs/s ({two['wall_seconds']:.2f} s, CPU {two['cpu_seconds']:.2f} s): "
            f"{rate(two) / rate(one):.2f} times 1 thread |",
            f"| peak memory, 10^4 runs | {m4['peak_rss_mib']:.1f} MiB |",
            f"| peak memory, 10^5 runs | {m5['peak_rss_mib']:.1f} MiB, {rate(m5):,.0f} runs/s |",
            f"| rhs evaluations per run | mean {study['rhs_evals_mean']:,.0f} |",
            "", f"Best of {study['repeat']} rounds, alternating thread counts; `{study['binary']}`."]


def run_bench(args):
    """The measure for `lab.main`; with `--out` elsewhere (another build), the results go there,
    the table is printed and the docs are left alone (the command ends here)."""
    cli = os.environ.get("CUSHION_BIN")
    if cli is None:
        lab.release("cushion")
        cli = lab.binary("cushion")
    study = measure(os.path.abspath(cli), args.repeat)
    if os.path.abspath(args.out) != RESULTS:
        with open(args.out, "w") as f:
            json.dump(study, f, indent=1)
            f.write("\n")
        print("\n".join(table(study)))
        sys.exit(0)
    return study


def blocks(study):
    return [(PERFORMANCE, "design-space-sweep", "\n".join(table(study)))]


def options(ap):
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=RESULTS, help="where to write the results (default lab/results/sweep_bench.json)")


def main():
    lab.main(__doc__, RESULTS, run_bench, blocks, options)


if __name__ == "__main__":
    main()
