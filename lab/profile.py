#!/usr/bin/env python3
"""Where a run's time goes: the share of each part of the hot path, per run, per evaluation of
the right-hand side and per step.

    python3 -m lab.profile            # needs valgrind (Debian package), under a minute after the build

For each case (two paper scenes at the defaults, one without its energy ledger, the steel
stops, DOP853 at rtol 1e-9) it counts instructions with valgrind's callgrind on `loop_scene`
and splits them by the inclusive cost of the functions that own each part:

- right-hand side: every call of `f` (`Observed::rhs`, with the force laws and `libm` calls it
  makes), wherever it is called from;
- stepping: the rest of `cushion_ode::solve` outside the parts below (stage arithmetic, error
  norm, controller, dense-output coefficients, the loop's copies and checks);
- events: `EventScan::scan` (chord bounds, sign tests, location, handlers);
- observers: `on_step` (the peak sampler, the early end, the ringing tail's checks);
- after the run: the summary and the ringing tail's closed form and ledger quadrature.

The shares are of instructions, not time; the wall time per run (`loop_scene`, natively) turns
them into ns (one timing each: the VM's noise of 10-20 % applies to the µs, not to the shares).
Steps and evaluations come from `cushion simulate --json`.
"""

import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = os.path.join(ROOT, os.environ.get("CARGO_TARGET_DIR", "target"))
LOOP = os.path.join(TARGET, "release", "loop_scene")
CLI = os.path.join(TARGET, "release", "cushion")
DT70 = "sweeps/scenes/paper-hydraulic-dt70.toml"
CASES = [
    # (label, scene, settings, runs under valgrind, runs timed)
    ("paper-hydraulic-dt70, dp5 rtol 1e-6", DT70, [], 100, 4000),
    ("paper-hydraulic-dt70, dp5 rtol 1e-6, ledger off", DT70, ["energy.ledger=false"], 100, 4000),
    ("paper-bistable-dt70, dp5 rtol 1e-6", "sweeps/scenes/paper-bistable-dt70.toml", [], 60, 3000),
    ("steel stops (stops.stiffness 1e11), dp5 rtol 1e-6", DT70, ["stops.stiffness=1e11"], 4, 150),
    ("paper-hydraulic-dt70, dop853 rtol 1e-9", DT70,
     ["solver.method=dop853", "solver.rtol=1e-9", "solver.atol=1e-12"], 20, 800),
]
OWNERS = {
    "rhs": r"<cushion_model::observe::Observed as cushion_ode::system::OdeSystem<_>>::rhs$",
    "solve": r"^cushion_ode::solve::solve$",
    "events": r"^cushion_ode::events::EventScan<_>::scan$",
    "observers": r"<cushion_model::observe::Observed as cushion_ode::system::OdeSystem<_>>::on_step$",
    "run": r"^cushion_model::simulate::simulate_valid$",
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
    hits = [v for k, v in costs.items() if re.search(OWNERS[key], k)]
    if len(hits) != 1:
        sys.exit(f"profile.py: {len(hits)} functions match {OWNERS[key]!r}; the build inlined or renamed it")
    return hits[0]


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
    args = [CLI, "simulate", scene, "--json"] + [a for s in sets for a in ("--set", s)]
    stats = json.loads(subprocess.run(args, cwd=ROOT, capture_output=True, text=True, check=True).stdout)["stats"]
    return dict(label=label, instructions=run / runs, us=us, evals=stats["rhs_evals"],
                steps=stats["steps"], rejected=stats["rejected"], parts={k: v / run for k, v in parts.items()})


def main():
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "cushion-studies", "--bin", "loop_scene"],
                   cwd=ROOT, check=True)
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "cushion"], cwd=ROOT, check=True)
    rows = [case(*c) for c in CASES]
    names = list(rows[0]["parts"])
    print("| case | µs/run | instructions/run | evaluations | steps (rejected) | ns/evaluation | ns/accepted step | "
          + " | ".join(names) + " | outside f |")
    print("|---" * (8 + len(names)) + "|")
    for r in rows:
        p = r["parts"]
        shares = " | ".join(f"{100 * p[k]:.0f} %" for k in names)
        print(f"| {r['label']} | {r['us']:.0f} | {r['instructions']:,.0f} | {r['evals']:,} | "
              f"{r['steps']:,} ({r['rejected']:,}) | {1000 * r['us'] / r['evals']:.0f} | "
              f"{1000 * r['us'] / r['steps']:.0f} | {shares} | "
              f"{100 * (1 - p['right-hand side']):.0f} % |")
    print("\nns per evaluation of f alone (its share of the wall time):")
    for r in rows:
        print(f"  {r['label']}: {1000 * r['us'] * r['parts']['right-hand side'] / r['evals']:.0f} ns")


if __name__ == "__main__":
    main()
