"""Wide random scenes at rtol 1e-6 against rtol 1e-11 (`cargo run --release -p cushion-studies
--bin wide_accuracy -- N [SEED]`): the median, 99th percentile and largest error of each summary
value over the scenes that detect an impact, the worst scenes, and the runs whose impact counts
differ.

    python3 -m lab.wide_accuracy [--scenes 4000]   # about 20 s after the studies crate's build
    python3 -m lab.wide_accuracy --tables          # docs/accuracy.md's block from the results

Writes lab/results/wide_accuracy.json; the block `wide-accuracy` of docs/accuracy.md is drawn
from it (here and by `python3 -m lab.make_docs`).
"""

import argparse
import json
import os
import re
import subprocess
import sys

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


def measure(scenes):
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


def sci(x):
    if x == 0:
        return "0"
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


def table(study):
    out = ["| | median | 99th percentile | largest |", "|---|---|---|---|"]
    for k, label in LABELS.items():
        f = study["fields"][k]
        out.append(f"| {label} | {sci(f['median'])} | {sci(f['p99'])} | {sci(f['largest'])} |")
    out += ["", f"{study['scenes']:,} scenes, {study['detect']:,} of which detect an impact, {study['not_ok']} not "
            f"`ok`; impact counts differ in {study['impact_counts_differ']} of the {study['detect']:,}."]
    return out


def write_block(study):
    from lab.make_docs import replace_block
    return replace_block(ACCURACY, "wide-accuracy", "\n".join(table(study)), "lab/results/wide_accuracy.json")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=4000)
    ap.add_argument("--tables", action="store_true", help="only rewrite the docs' block from the results")
    args = ap.parse_args()
    if not args.tables:
        study = measure(args.scenes)
        with open(RESULTS, "w") as f:
            json.dump(study, f, indent=1)
            f.write("\n")
    with open(RESULTS) as f:
        study = json.load(f)
    print("\n".join(table(study)))
    sys.exit(0 if write_block(study) else 1)


if __name__ == "__main__":
    main()
