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

import argparse
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "ringing_tail_check.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
HEAD = re.compile(r"^(\d+) scenes, ringing tail taken in (\d+); steps (\d+) -> (\d+) .*; counts differ in (\d+)")
WORST = re.compile(r"^worst (\w+)\s+(\S+)\s*(.*)$")


def measure(scenes):
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


def sci(x):
    if x == 0:
        return "0"
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


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


def write_block(study):
    from lab.make_docs import replace_block
    return replace_block(ACCURACY, "ringing-tail-check", block(study), "lab/results/ringing_tail_check.json")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=1000)
    ap.add_argument("--tables", action="store_true", help="only rewrite the docs' block from the results")
    args = ap.parse_args()
    if not args.tables:
        study = measure(args.scenes)
        with open(RESULTS, "w") as f:
            json.dump(study, f, indent=1)
            f.write("\n")
    with open(RESULTS) as f:
        study = json.load(f)
    print(block(study))
    sys.exit(0 if write_block(study) else 1)


if __name__ == "__main__":
    main()
