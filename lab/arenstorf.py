"""DOP853 against DOPRI5 on the Arenstorf orbit over one period (`rtol = atol = tol`, 1e-4 to
1e-12): steps, rejections, evaluations, the end error and µs per solve, from
`cargo bench -p cushion-ode --bench step_cost` (Hairer's DOPRI5 on the same orbit:
`lab/arenstorf_dopri5.py`).

    python3 -m lab.arenstorf            # about a minute with the bench's build
    python3 -m lab.arenstorf --tables   # docs/integrator.md's block from the results

Writes lab/results/arenstorf.json; the block `arenstorf` of docs/integrator.md is drawn from it
(here and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys

from lab import study as lab
from lab.study import rt, sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "arenstorf.json")
INTEGRATOR = os.path.join(ROOT, "docs", "integrator.md")
ROW = re.compile(r"^\s*(dp5|dop853)\s+(\S+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\S+)\s+([\d.]+)$")
# The tolerances the page shows: where DOP853 pays off.
SHOWN = [1e-9, 1e-10, 1e-11, 1e-12]


def measure(args=None):
    out = subprocess.run(["cargo", "bench", "-q", "-p", "cushion-ode", "--bench", "step_cost"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        m = ROW.match(line)
        if m:
            method, tol, steps, rejected, evals, err, us = m.groups()
            rows.append({"method": method, "tol": float(tol), "steps": int(steps), "rejected": int(rejected),
                         "rhs_evals": int(evals), "end_error": float(err), "us_per_solve": float(us)})
    if not rows:
        sys.exit("arenstorf.py: the bench printed no rows:\n" + out)
    return {"rows": rows}


def table(study):
    at = {(r["method"], r["tol"]): r for r in study["rows"]}
    out = ["| tol | DOP853 error | evaluations (steps, rejected) | DOPRI5 error | evaluations |",
           "|---|---|---|---|---|"]
    for tol in SHOWN:
        d8, d5 = at[("dop853", tol)], at[("dp5", tol)]
        out.append(f"| {rt(tol)} | {sci(d8['end_error'])} | {d8['rhs_evals']:,} ({d8['steps']}, "
                   f"{d8['rejected']}) | {sci(d5['end_error'])} | {d5['rhs_evals']:,} |")
    return out


def blocks(study):
    return [(INTEGRATOR, "arenstorf", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
