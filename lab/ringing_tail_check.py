"""The ringing tail against the run integrated to `t_end` on random design-space scenes with
brake decelerations of 5-30 m/s^2 (`cargo run --release -p cushion-studies --bin
ringing_tail_check -- N`): how often the tail is taken, the steps it saves, whether impact counts
differ, and the largest difference of each summary value (relative to its scale, the robot
impulse to `(m_t + m_p) v_max`) with the scene that makes it.

    python3 -m lab.ringing_tail_check [--scenes 1000]   # about 15 s after the studies crate's build
    python3 -m lab.ringing_tail_check --tables          # docs/accuracy.md's block from the results

Writes lab/results/ringing_tail_check.json; the block `ringing-tail-check` of docs/accuracy.md
is drawn from it (here and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys

from lab import study as lab
from lab.study import sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "ringing_tail_check.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
HEAD = re.compile(r"^(\d+) scenes, ringing tail taken in (\d+); steps (\d+) -> (\d+) .*; counts differ in (\d+)")
WORST = re.compile(r"^worst (\w+)\s+(\S+)\s*(.*)$")


def measure(args):
    scenes = args.scenes
    out = subprocess.run(["cargo", "run", "--release", "-q", "-p", "cushion-studies", "--bin", "ringing_tail_check",
                          "--", str(scenes)], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    study = {"worst": {}}
    for line in out.splitlines():
        if m := HEAD.match(line):
            study.update(scenes=int(m[1]), taken=int(m[2]), steps_off=int(m[3]), steps_on=int(m[4]),
                         counts_differ=int(m[5]))
        elif m := WORST.match(line):
            study["worst"][m[1]] = {"difference": float(m[2]), "scene": m[3].strip()}
    if "taken" not in study or not study["worst"]:
        sys.exit("ringing_tail_check.py: the study's output was not understood:\n" + out)
    return study


def block(study):
    w = study["worst"]
    same = [k.replace("_", " ") for k in ("object_final_velocity", "max_stroke", "peak_robot_force")
            if w[k]["difference"] == 0]
    moved = [f"{k.replace('_', ' ')} within {sci(w[k]['difference'])}"
             for k in ("object_final_velocity", "max_stroke", "peak_robot_force") if w[k]["difference"] != 0]
    return "\n".join([
        f"The tail is taken in {study['taken']:,} of {study['scenes']:,} scenes, with "
        f"{study['steps_off'] / study['steps_on']:.2f} times fewer steps; impact counts differ in "
        f"{study['counts_differ']}; " + (", ".join(same) + " identical; " if same else "")
        + ("".join(m + "; " for m in moved))
        + f"robot impulse within {sci(w['robot_impulse']['difference'])} of `(m_t + m_p) v_max`, energy residual "
        f"within {sci(w['energy_residual']['difference'])} of the integrated run's.",
    ])


def blocks(study):
    return [(ACCURACY, "ringing-tail-check", block(study))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks,
             options=lambda ap: ap.add_argument("--scenes", type=int, default=1000))


if __name__ == "__main__":
    main()
