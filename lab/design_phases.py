#!/usr/bin/env python3
"""Where the design space's steps go: a seeded sample of the runs of `sweeps/design-space.toml`,
each run's accepted steps split at its last contact event (the last begin or end of an object or
stop contact before the early end) into the impact and what follows it up to the early end.

    .venv/bin/python -m lab.design_phases [--sample 400] [--seed 2]    # about 10 s
    .venv/bin/python -m lab.design_phases --tables   # docs/performance.md's block from the results

After the last contact event only the tool's motion on the stop that holds it is left: it rings
there, or settles, until the ringing tail or the rest test ends the run (`docs/model.md`, Early
end and ringing tail). The steps of that phase are what a closed form that took over sooner
could save. Printed per module and per robot phase at the end (braking once the sensor
switched, or cruising to `t_end` when it never does or the dead time ends after the run). A
benchmark, not a test. Writes lab/results/design_phases.json; the block `design-phases` of
docs/performance.md ("The design-space sweep") is drawn from it (here and by
`python3 -m lab.make_docs`).
"""

import os
import tomllib

from lab import study as lab
from lab.make_docs import PERFORMANCE

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SWEEP = os.path.join(ROOT, "sweeps/design-space.toml")
RESULTS = os.path.join(ROOT, "lab", "results", "design_phases.json")
SCENE = os.path.join(ROOT, "sweeps/scenes/paper-hydraulic-dt70.toml")
AXES = ["robot.dead_time", "hydraulic.gas_pressure", "hydraulic.orifice_radius", "object.mass", "module"]
# events that are not contacts: the robot's and the sensor's, and the early end itself
NOT_CONTACT = {"sensor", "brake", "robot_stopped", "early_end"}
with open(SCENE, "rb") as f:
    T_END = tomllib.load(f)["t_end"]  # s; the sweep sets no other


def phases(point):
    """Accepted steps before and after the last contact event, up to the early end."""
    import cushion
    import numpy as np

    run = cushion.simulate(SCENE, set=point, sample_interval=0.0)
    ev = run.events
    ends = ev.t[ev.event == "early_end"]
    end = float(ends.iloc[0]) if len(ends) else float("inf")
    contacts = ev.t[~ev.event.isin(NOT_CONTACT) & (ev.t < end)]
    last = float(contacts.max()) if len(contacts) else 0.0
    # every step's end, plus a point per event that shares the time of the step it cut
    t = np.unique(np.asarray(run.t))
    t = t[(t > 0.0) & (t <= end)]
    after = int(np.sum(t > last))
    return len(t) - after, after


def measure(args):
    sample, seed = args.sample, args.seed
    import cushion
    import numpy as np
    import pandas as pd

    design = cushion.sweep(SWEEP, progress=False)
    rng = np.random.default_rng(seed)
    rows = []
    for i in rng.choice(len(design), sample, replace=False):
        r = design.iloc[i]
        point = {k: (str(r[k]) if k == "module" else float(r[k])) for k in AXES}
        before, after = phases(point)
        cruises = not (r.t_brake < T_END)  # no brake before t_end (NaN: the sensor never switched)
        rows.append(dict(module=r.module, robot="cruises to t_end" if cruises else "brakes", runs=1,
                         steps=before + after, after_last_contact=after))
    g = pd.DataFrame(rows).groupby(["module", "robot"])[["runs", "steps", "after_last_contact"]].sum()
    groups = [{"module": m, "robot": robot, **{k: int(v) for k, v in row.items()}}
              for (m, robot), row in g.iterrows()]
    return {"sample": sample, "seed": seed, "groups": groups}


def table(study):
    total = sum(g["steps"] for g in study["groups"])
    after = sum(g["after_last_contact"] for g in study["groups"])
    robot = {"brakes": "brakes", "cruises to t_end": "cruises to `t_end` (the sensor never switches)"}
    out = ["| module, robot | runs | steps | after the last contact: share of its steps | of all steps |",
           "|---|---|---|---|---|"]
    for g in study["groups"]:
        out.append(f"| {g['module']}, {robot[g['robot']]} | {g['runs']:,} | {g['steps']:,} | "
                   f"{100 * g['after_last_contact'] / g['steps']:.0f} % | {100 * g['after_last_contact'] / total:.1f} % |")
    out += ["", f"{study['sample']} runs (seed {study['seed']}): {100 * after / total:.0f} % of the accepted steps come "
            "after a run's last contact event."]
    return out


def blocks(study):
    return [(PERFORMANCE, "design-phases", "\n".join(table(study)))]


def options(ap):
    ap.add_argument("--sample", type=int, default=400)
    ap.add_argument("--seed", type=int, default=2)


def main():
    lab.main(__doc__.split("\n\n")[0], RESULTS, measure, blocks, options)


if __name__ == "__main__":
    main()
