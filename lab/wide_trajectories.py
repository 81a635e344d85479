"""Peaks against the recorded trajectories of 20,000 wide random scenes (`cargo run --release -p
cushion-studies --bin wide_trajectories -- 20000 [--rtol R]`), at each scene's own tolerance and
at rtol 1e-6, 1e-4 and 1e-3: the runs, not flagged stiff, with a trajectory sample above a
reported peak by more than rtol of its scale, counting forces of at least 10 mN (below that a
force is the integration error's own size).

    python3 -m lab.wide_trajectories            # about 2 minutes after the studies crate's build
    python3 -m lab.wide_trajectories --tables   # docs/accuracy.md's block from the results

Writes lab/results/wide_trajectories.json (every listed mismatch, filtered or not); the block
`wide-trajectories` of docs/accuracy.md is drawn from it (here and by `python3 -m lab.make_docs`).
"""

import argparse
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results", "wide_trajectories.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
SCENES = 20_000
TOLERANCES = [None, 1e-6, 1e-4, 1e-3]  # None: each scene's own
FORCE_FLOOR = 0.01  # N
HEAD = re.compile(r"^(\d+) runs checked")
MISMATCH = re.compile(r"^\s+(\d+) \((\w+), rtol (\S+?)(, stiff)?\): (.+?) sample (\S+) above the peak (\S+) \(([\d.]+) rtol\)")


def run(rtol):
    args = ["cargo", "run", "--release", "-q", "-p", "cushion-studies", "--bin", "wide_trajectories", "--", str(SCENES)]
    if rtol is not None:
        args += ["--rtol", f"{rtol:g}"]
    out = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, check=True).stdout
    checked = next((int(m[1]) for line in out.splitlines() if (m := HEAD.match(line))), None)
    if checked is None:
        sys.exit("wide_trajectories.py: the study's output was not understood:\n" + out)
    mismatches = []
    for line in out.splitlines():
        if m := MISMATCH.match(line):
            mismatches.append({"scene": int(m[1]), "module": m[2], "rtol": float(m[3]), "stiff": bool(m[4]),
                               "quantity": m[5], "sample": float(m[6]), "peak": float(m[7]), "rtols_above": float(m[8])})
    return {"rtol": rtol, "checked": checked, "mismatches": mismatches}


def counted(m):
    """A mismatch the page counts: not flagged stiff, a force of at least the floor."""
    force = m["quantity"] in ("|F_r|", "F_c")
    return not m["stiff"] and (not force or m["sample"] >= FORCE_FLOOR)


def table(study):
    out = ["| tolerance | runs |", "|---|---|"]
    for r in study["runs"]:
        label = "each scene's own (1e-9 to 1e-3)" if r["rtol"] is None else "rtol {}e{}".format(
            *(lambda m, e: (m, int(e)))(*f"{r['rtol']:.0e}".split("e")))
        runs = len({m["scene"] for m in r["mismatches"] if counted(m)})
        out.append(f"| {label} | {runs} |")
    return out


def write_block(study):
    from lab.make_docs import replace_block
    return replace_block(ACCURACY, "wide-trajectories", "\n".join(table(study)), "lab/results/wide_trajectories.json")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tables", action="store_true", help="only rewrite the docs' block from the results")
    args = ap.parse_args()
    if not args.tables:
        study = {"scenes": SCENES, "force_floor": FORCE_FLOOR, "runs": [run(r) for r in TOLERANCES]}
        with open(RESULTS, "w") as f:
            json.dump(study, f, indent=1)
            f.write("\n")
    with open(RESULTS) as f:
        study = json.load(f)
    print("\n".join(table(study)))
    sys.exit(0 if write_block(study) else 1)


if __name__ == "__main__":
    main()
