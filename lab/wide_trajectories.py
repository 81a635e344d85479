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

import os
import re
import subprocess
import sys

from lab import study as lab
from lab.study import rt

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
        label = "each scene's own (1e-9 to 1e-3)" if r["rtol"] is None else f"rtol {rt(r['rtol'])}"
        runs = len({m["scene"] for m in r["mismatches"] if counted(m)})
        out.append(f"| {label} | {runs} |")
    return out


def measure(args=None):
    return {"scenes": SCENES, "force_floor": FORCE_FLOOR, "runs": [run(r) for r in TOLERANCES]}


def blocks(study):
    return [(ACCURACY, "wide-trajectories", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
