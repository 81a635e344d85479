#!/usr/bin/env python3
"""Where a run's time goes: the share of each part of the hot path, per run, per evaluation of
the right-hand side and per step.

    python3 -m lab.profile            # needs valgrind (Debian package), under a minute after the build
    python3 -m lab.profile --tables   # docs/performance.md's table from lab/results/profile.json

For each case (two paper scenes at the defaults, one without its energy ledger, the steel
stops, DOP853 at rtol 1e-9) it counts instructions with valgrind's callgrind on `loop_scene`
and splits them by the inclusive cost of the functions that own each part:

- right-hand side: every call of `f` (the model's `OdeSystem::rhs`, with the force laws and
  `libm` calls it makes), wherever it is called from;
- stepping: the rest of `cushion_ode::solve_observed` outside the parts below (stage arithmetic, error
  norm, controller, dense-output coefficients, the loop's copies and checks);
- events: `EventScan::scan` (chord bounds, sign tests, location, handlers);
- observers: the model's observers (`observe::Watchers`): the peak sampler's `sample` and the
  check for the early end after each step (the ringing tail's checks);
- after the run: the summary and the ringing tail's closed form and ledger quadrature.

The shares are of instructions, not time; the wall time per run (`loop_scene`, natively) turns
them into ns (one timing each: the VM's noise of 10-20 % applies to the µs, not to the shares).
Steps and evaluations come from `cushion simulate --json`. The cases' figures go to
lab/results/profile.json; docs/performance.md's `run-time-parts` block is drawn from that file
(here, with `--tables`, and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys
import tempfile

from lab import study as lab
from lab.make_docs import PERFORMANCE

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOOP = lab.binary("loop_scene")
RESULTS = os.path.join(ROOT, "lab", "results", "profile.json")
BLOCK = "run-time-parts"
DT70 = "sweeps/scenes/paper-hydraulic-dt70.toml"
CASES = [
    # (label, ...): the first two are the same scene with and without the ledger (see `table`).
    # (label, scene, settings, runs under valgrind, runs timed)
    ("paper-hydraulic-dt70, dp5 rtol 1e-6", DT70, [], 100, 4000),
    ("paper-hydraulic-dt70, dp5 rtol 1e-6, ledger off", DT70, ["energy.ledger=false"], 100, 4000),
    ("paper-bistable-dt70, dp5 rtol 1e-6", "sweeps/scenes/paper-bistable-dt70.toml", [], 60, 3000),
    ("steel stops (stops.stiffness 1e11), dp5 rtol 1e-6", DT70, ["stops.stiffness=1e11"], 4, 150),
    ("paper-hydraulic-dt70, dop853 rtol 1e-9", DT70,
     ["solver.method=dop853", "solver.rtol=1e-9", "solver.atol=1e-12"], 20, 800),
]
# Each part: the functions that own it (one match each; their inclusive costs are summed, so
# none may call another of its list).
OWNERS = {
    "rhs": [r"OdeSystem<_> for cushion_model::model::Model>::rhs$"],
    "solve": [r"^cushion_ode::solve::solve_observed$"],
    "events": [r"^cushion_ode::events::EventScan<_>::scan$"],
    "observers": [r"^cushion_model::peaks::sampler::PeakSampler::sample(<.*>)?$",
                  r"^cushion_model::early_end::watch::PeaksThenEarlyEnd::ends_early$"],
    "run": [r"^cushion_model::simulate::simulate_valid$"],
}
LINE = re.compile(r"^\s*([\d,]+) \([ \d.]+%\)\s+(\S.*?):(.+?) \[")


def inclusive(out_file):
    """{function name: inclusive instructions} from callgrind_annotate."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out_file],
                          capture_output=True, text=True, check=True).stdout
    costs = {}
    for line in text.splitlines():
        m = LINE.match(line)
        if m:
            costs.setdefault(m.group(3), int(m.group(1).replace(",", "")))
    return costs


def owner(costs, key):
    total = 0
    for pattern in OWNERS[key]:
        hits = [v for k, v in costs.items() if re.search(pattern, k)]
        if len(hits) != 1:
            sys.exit(f"profile.py: {len(hits)} functions match {pattern!r}; the build inlined or renamed it")
        total += hits[0]
    return total


def case(label, scene, sets, runs, timed):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", LOOP, str(runs),
                        scene, *sets], cwd=ROOT, capture_output=True, check=True)
        c = inclusive(out)
    run, solve, rhs = owner(c, "run"), owner(c, "solve"), owner(c, "rhs")
    events, observers = owner(c, "events"), owner(c, "observers")
    parts = {"right-hand side": rhs, "stepping": solve - rhs - events - observers, "events": events,
             "observers": observers, "after the run": run - solve}
    wall = subprocess.run([LOOP, str(timed), scene, *sets], cwd=ROOT, capture_output=True, text=True,
                          check=True).stdout
    us = float(wall.split()[0])
    stats = lab.simulate(scene, sets)["stats"]
    return dict(label=label, instructions=run / runs, us=us, evals=stats["rhs_evals"],
                steps=stats["steps"], rejected=stats["rejected"], parts={k: v / run for k, v in parts.items()})


def table(rows):
    """The block's table and the figures read from it."""
    names = list(rows[0]["parts"])
    out = ["| case | µs/run | instructions/run | evaluations | steps (rejected) | ns/evaluation | "
           "ns/accepted step | " + " | ".join(names) + " | outside f |",
           "|---" * (8 + len(names)) + "|"]
    for r in rows:
        p = r["parts"]
        shares = " | ".join(f"{100 * p[k]:.0f} %" for k in names)
        out.append(f"| {r['label']} | {r['us']:.0f} | {r['instructions']:,.0f} | {r['evals']:,} | "
                   f"{r['steps']:,} ({r['rejected']:,}) | {1000 * r['us'] / r['evals']:.0f} | "
                   f"{1000 * r['us'] / r['steps']:.0f} | {shares} | "
                   f"{100 * (1 - p['right-hand side']):.0f} % |")
    f_alone = [1000 * r["us"] * r["parts"]["right-hand side"] / r["evals"] for r in rows]
    whole = [1000 * r["us"] / r["evals"] for r in rows]
    h = rows[0]
    per_step = {k: h["instructions"] * v / h["steps"] for k, v in h["parts"].items()}
    out += ["", f"`f` alone costs {min(f_alone):.0f}-{max(f_alone):.0f} ns per evaluation (its share "
            f"of the wall time), the whole run {min(whole):.0f}-{max(whole):.0f} ns. On the first "
            f"case a step costs about {h['instructions'] / h['steps']:,.0f} instructions: `f` "
            f"{per_step['right-hand side']:,.0f} ({h['evals'] / h['steps']:.1f} evaluations), the "
            f"stepping {per_step['stepping']:,.0f}, the event scan {per_step['events']:,.0f}, the "
            f"observers {per_step['observers']:,.0f}; after the run, "
            f"{100 * h['parts']['after the run']:.0f} % of the run's instructions. Without the "
            f"energy ledger (its two states and its tail quadrature) the run takes "
            f"{100 * (1 - rows[1]['instructions'] / h['instructions']):.0f} % fewer instructions."]
    return out


def measure(args=None):
    lab.release("loop_scene", package="cushion-studies")
    lab.release("cushion")
    return {"cases": [case(*c) for c in CASES]}


def blocks(study):
    return [(PERFORMANCE, BLOCK, "\n".join(table(study["cases"])))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
