"""Cost against accuracy of the paper scenes, one row per tolerance: rtol 1e-3 .. 1e-10 with
atol = rtol / 1000 (the scenes' own ratio), against the same scene at rtol 1e-12.

    python3 -m lab.scene_tolerances            # needs valgrind (Debian package); a few minutes
    python3 -m lab.scene_tolerances --tables   # the docs' tables from the results alone

Per scene and rtol (`tolerance_row`, the studies crate): steps and right-hand-side evaluations;
the best wall time per run over 5 batches; the errors against rtol 1e-12 of the detection time
(s), the peak robot force (relative), the robot impulse (N s), the object's final speed (m/s)
and the largest stroke (m); the energy ledger's residual; the impact counts of both runs. Beside
it, instructions per run (valgrind's cachegrind on `loop_scene`: (50 runs - 0 runs) / 50), and,
for the hydraulic scene, the evaluations with the ringing tail off (`cushion simulate --json`).

Writes lab/results/scene_tolerances.json; the blocks `scene-tolerances-errors` of
docs/accuracy.md and `scene-tolerances-cost` of docs/performance.md are drawn from it (here and
by `python3 -m lab.make_docs`).
"""

import json
import os
import subprocess
import sys

from lab import study as lab
from lab.make_docs import PERFORMANCE
from lab.study import rt

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "scene_tolerances.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
SCENES = {
    "hydraulic dt70": "sweeps/scenes/paper-hydraulic-dt70.toml",
    "bistable dt70": "sweeps/scenes/paper-bistable-dt70.toml",
    "rigid": "sweeps/scenes/paper-rigid.toml",
}
RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
# The accuracy page shows a selection of the tolerances.
SHOWN = [1e-3, 1e-4, 1e-6, 1e-8, 1e-10]
# The ringing tail on and off, on the hydraulic scene.
TAIL_RTOLS = [1e-6, 1e-7, 1e-8]


def tolerances(rtol):
    return [f"solver.rtol={rtol:.0e}", f"solver.atol={rtol / 1000:.0e}"]


def instructions(scene, rtol):
    return lab.instructions_per_run([scene, *tolerances(rtol)], 50)


def evaluations(scene, sets):
    return lab.simulate(scene, sets)["stats"]["rhs_evals"]


def measure(args=None):
    lab.release("tolerance_row", "loop_scene", package="cushion-studies")
    lab.release("cushion")
    scenes = {}
    for name, scene in SCENES.items():
        rows = []
        for rtol in RTOLS:
            out = subprocess.run([lab.binary("tolerance_row"), scene, f"{rtol:.0e}"], cwd=ROOT,
                                 capture_output=True, text=True, check=True).stdout
            row = json.loads(out)
            row["instructions_per_run"] = instructions(scene, rtol)
            rows.append(row)
            print(name, json.dumps(row), file=sys.stderr)
        scenes[name] = {"scene": scene, "rows": rows}
    hydraulic = SCENES["hydraulic dt70"]
    tail = [{"rtol": r, "rhs_evals_on": evaluations(hydraulic, tolerances(r)),
             "rhs_evals_off": evaluations(hydraulic, tolerances(r) + ["solver.ringing_tail=false"])}
            for r in TAIL_RTOLS]
    return {"scenes": scenes, "ringing_tail": tail}


def e(x):
    """An error to two figures; "-" where the run has no such value, "differs" where only one of
    the two runs has it."""
    if x is None or isinstance(x, str):
        return "-" if x is None else x
    return "0" if x == 0 else f"{x:.1e}"


def errors_table(study):
    out = ["| scene | rtol | object final speed (m/s) | peak `F_r` (rel) | robot impulse (N s) | "
           "detection time (s) | energy residual | impacts as at rtol 1e-12 |",
           "|---|---|---|---|---|---|---|---|"]
    for name, s in study["scenes"].items():
        first = True
        for r in s["rows"]:
            if r["rtol"] not in SHOWN:
                continue
            same = "yes" if r["impacts"] == r["reference_impacts"] else (
                f"no: {r['impacts']} against {r['reference_impacts']}")
            out.append(f"| {name if first else ''} | {rt(r['rtol'])} | {e(r['object_final_velocity'])} | "
                       f"{e(r['peak_robot_force_rel'])} | {e(r['robot_impulse'])} | {e(r['t_detect'])} | "
                       f"{e(r['energy_residual'])} | {same} |")
            first = False
    out += ["", "Impact counts are (object, forward stop, back stop)."]
    return out


def cost_table(study):
    names = list(study["scenes"])
    out = ["| rtol | " + " | ".join(f"{n}: steps, evaluations, µs, instructions" for n in names) + " |",
           "|---" * (1 + len(names)) + "|"]
    for i, rtol in enumerate(RTOLS):
        cells = []
        for n in names:
            r = study["scenes"][n]["rows"][i]
            cells.append(f"{r['steps']:,}, {r['rhs_evals']:,}, {r['us_per_run']:,.0f}, "
                         f"{r['instructions_per_run']:,}")
        out.append(f"| {rt(rtol)} | " + " | ".join(cells) + " |")
    tail = study["ringing_tail"]
    out += ["", "The hydraulic scene's evaluations at rtol "
            + ", ".join(rt(t["rtol"]) for t in tail) + ": "
            + ", ".join(f"{t['rhs_evals_on']:,}" for t in tail) + " with the ringing tail, "
            + ", ".join(f"{t['rhs_evals_off']:,}" for t in tail) + " without it."]
    return out


def blocks(study):
    return [(ACCURACY, "scene-tolerances-errors", "\n".join(errors_table(study))),
            (PERFORMANCE, "scene-tolerances-cost", "\n".join(cost_table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
