"""Wide random scenes at rtol 1e-6 against rtol 1e-11 (`cargo run --release -p cushion-studies
--bin wide_accuracy -- N [SEED]`): the median, 99th percentile and largest error of each summary
value over the scenes that detect an impact, the worst scenes, and the runs whose impact counts
differ.

    python3 -m lab.wide_accuracy [--scenes 4000]   # about 20 s after the studies crate's build
    python3 -m lab.wide_accuracy --tables          # docs/accuracy.md's block from the results

Writes lab/results/wide_accuracy.json; the block `wide-accuracy` of docs/accuracy.md is drawn
from it (here and by `python3 -m lab.make_docs`).
"""

import os
import re
import subprocess
import sys

from lab import study as lab
from lab.study import sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "wide_accuracy.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
LABELS = {
    "object_final_velocity": "object final speed",
    "robot_impulse": "robot impulse",
    "peak_robot_force": "peak robot force",
    "peak_contact_force": "peak contact force",
    "max_gas_pressure": "max gas pressure",
    "max_stroke": "max stroke",
    "t_detect": "detection time",
}
HEAD = re.compile(r"^(\d+) scenes, (\d+) detect an impact .*?, (\d+) not ok")
ROW = re.compile(r"^(\w+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(.*)$")
DIFFER = re.compile(r"^impact counts differ in (\d+) runs")


def measure(args):
    scenes = args.scenes
    out = subprocess.run(["cargo", "run", "--release", "-q", "-p", "cushion-studies", "--bin", "wide_accuracy", "--",
                          str(scenes)], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    study = {"fields": {}}
    for line in out.splitlines():
        if m := HEAD.match(line):
            study.update(scenes=int(m[1]), detect=int(m[2]), not_ok=int(m[3]))
        elif m := DIFFER.match(line):
            study["impact_counts_differ"] = int(m[1])
        elif (m := ROW.match(line)) and m[1] in LABELS:
            study["fields"][m[1]] = {"median": float(m[2]), "p99": float(m[3]), "largest": float(m[4]),
                                     "worst": m[5].strip()}
    if len(study["fields"]) != len(LABELS) or "detect" not in study:
        sys.exit("wide_accuracy.py: the study's output was not understood:\n" + out)
    return study


def table(study):
    out = ["| | median | 99th percentile | largest |", "|---|---|---|---|"]
    for k, label in LABELS.items():
        f = study["fields"][k]
        out.append(f"| {label} | {sci(f['median'])} | {sci(f['p99'])} | {sci(f['largest'])} |")
    out += ["", f"{study['scenes']:,} scenes, {study['detect']:,} of which detect an impact, {study['not_ok']} not "
            f"`ok`; impact counts differ in {study['impact_counts_differ']} of the {study['detect']:,}."]
    return out


def blocks(study):
    return [(ACCURACY, "wide-accuracy", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks,
             options=lambda ap: ap.add_argument("--scenes", type=int, default=4000))


if __name__ == "__main__":
    main()
