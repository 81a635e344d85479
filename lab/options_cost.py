"""What options cost: one run of each paper scene and of the hydraulic scene with optional parts
absent or present, from `cargo bench -p cushion-model --bench scene` (in-process, release, the
median of 7 batches; evaluations and steps are exact).

    python3 -m lab.options_cost            # about half a minute after the bench's build
    python3 -m lab.options_cost --tables   # docs/performance.md's block from the results

Writes lab/results/options_cost.json (one row per line of the bench); the block `options-cost`
of docs/performance.md is drawn from it (here and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys

from lab import study as lab
from lab.make_docs import PERFORMANCE

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "options_cost.json")
# label, states, µs/run, evaluations, steps, rejected, ns per evaluation, object final speed
ROW = re.compile(r"^(\S.*?)\s+(\d+)\s+([\d.]+)\s+(\d+)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+(\S+)$")


def measure(args=None):
    out = subprocess.run(["cargo", "bench", "-q", "-p", "cushion-model", "--bench", "scene"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        m = ROW.match(line)
        if m:
            label, states, us, evals, steps, rejected, _, _ = m.groups()
            rows.append({"variant": label, "states": int(states), "us_per_run": float(us),
                         "rhs_evals": int(evals), "steps": int(steps), "rejected": int(rejected)})
    if not rows:
        sys.exit("options_cost.py: the bench printed no rows:\n" + out)
    return {"rows": rows}


def table(study):
    out = ["| variant | states | µs/run | rhs evaluations | steps (rejected) |", "|---|---|---|---|---|"]
    for r in study["rows"]:
        out.append(f"| {r['variant']} | {r['states']} | {r['us_per_run']:.0f} | {r['rhs_evals']:,} | "
                   f"{r['steps']:,} ({r['rejected']:,}) |")
    by = {r["variant"]: r for r in study["rows"]}
    off, on, short = (by.get("early end off, t_end 1.5 s"), by.get("early end on, t_end 1.5 s"),
                      by.get("ledger on (default: 6 states)"))
    if off and on and short:
        out += ["", f"A 1.5 s run costs {on['us_per_run']:.0f} µs with the early end and {off['us_per_run']:.0f} µs "
                f"without it; the default 0.3 s run {short['us_per_run']:.0f} µs."]
    return out


def blocks(study):
    return [(PERFORMANCE, "options-cost", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
