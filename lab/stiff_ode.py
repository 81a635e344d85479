"""The implicit method (rodas) on the classic stiff problems: work (steps, evaluations of f,
Jacobians, LU factorizations), accuracy against the published reference, wall time; DOPRI5
beside it where it finishes; then SciPy's Radau and BDF on the same problems
(`lab/stiff_scipy.py`).

    .venv/bin/python -m lab.stiff_ode            # a few seconds after the studies crate's build
    .venv/bin/python -m lab.stiff_ode --tables   # docs/integrator.md's block from the results

The engine's rows come from `cargo run --release -p cushion-studies --bin stiff_ode`. Writes
lab/results/stiff_ode.json; the block `stiff-ode` of docs/integrator.md is drawn from it (here
and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys

from lab import study as lab

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "stiff_ode.json")
INTEGRATOR = os.path.join(ROOT, "docs", "integrator.md")
# The problems as the page names them (the engine's names are the keys).
PROBLEMS = {
    "VDPOL mu=1e6": "VDPOL `mu = 1e6`, `y0 = (2, 0)`, `[0, 2]` (1e-6)",
    "ROBER": "ROBER `[0, 1e11]` (1e-10, 1e-16, 1e-10)",
    "HIRES": "HIRES `[0, 321.8122]` (1e-10)",
    "OREGO": "OREGO `[0, 360]` (1e-8)",
}


def engine_rows():
    out = subprocess.run(["cargo", "run", "--release", "-q", "-p", "cushion-studies", "--bin", "stiff_ode"],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines()[1:]:
        cells = re.split(r"\s{2,}", line.strip())
        if len(cells) != 9:
            continue
        problem, method, steps, rejected, evals, jacs, lus, err, wall = cells
        rows.append({"problem": problem, "method": method.replace(" (FD)", ", FD"), "steps": int(steps),
                     "rejected": int(rejected), "rhs_evals": int(evals), "jacobians": int(jacs), "lus": int(lus),
                     "mixed_error": None if err == "MaxSteps" else float(err), "wall_ms": float(wall)})
    if not rows:
        sys.exit("stiff_ode.py: the stiff_ode binary printed no rows:\n" + out)
    return rows


def measure(args=None):
    from lab import stiff_scipy

    return {"engine": engine_rows(), "scipy": [r for r in stiff_scipy.rows() if r["problem"] in PROBLEMS]}


def wall(ms):
    return f"{ms:.2f}" if ms < 1 else f"{ms:.1f}" if ms < 10 else f"{ms:.0f}"


def mixed(x):
    return f"{x:.2f}" if x < 10 else f"{x:.0f}"


def table(study):
    out = ["| problem (atol) | method | steps | rejected | `f` | Jacobians | LUs | mixed error | wall ms |",
           "|---|---|---|---|---|---|---|---|---|"]
    for key, label in PROBLEMS.items():
        first = True
        for r in [r for r in study["engine"] if r["problem"] == key] + [r for r in study["scipy"] if r["problem"] == key]:
            name = label if first else ""
            first = False
            implicit = r["method"].startswith(("rodas", "SciPy"))
            if r.get("mixed_error") is None:
                out.append(f"| {name} | {r['method']} | stopped at {r['steps']:,} steps | | | | | | {wall(r['wall_ms'])} |")
                continue
            out.append(f"| {name} | {r['method']} | {r['steps']} | {r.get('rejected', '')} | {r['rhs_evals']} | "
                       f"{r['jacobians'] if implicit else ''} | {r['lus'] if implicit else ''} | "
                       f"{mixed(r['mixed_error'])} | {wall(r['wall_ms'])} |")
    return out


def blocks(study):
    return [(INTEGRATOR, "stiff-ode", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
