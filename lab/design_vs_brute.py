"""The design search against brute force: for three design questions, `cushion.design` at its
defaults (resolution 1/64, tolerance 1e-3) against every design point of the 1/64 lattice (65
points per range axis, every value of a list axis) run on a 21 x 21 grid of its `for_all` box.

    .venv/bin/python -m lab.design_vs_brute            # runs (about 6 M runs), writes lab/results/design_vs_brute.json
    .venv/bin/python -m lab.design_vs_brute --tables   # docs/design.md's table from the JSON

For each question: the search's runs and wall time (2 threads) against the brute force's; the
lattice points where the brute force's margin exceeds 1 % and the refined map's classification
disagrees with it; and, at every design point the search evaluated (all on the lattice), how far
its worst case is below the brute force's (never, or within the tolerance, is the target) or
above it (the search finds worst cases between the brute force's grid points)."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import time

import numpy as np
import pandas as pd

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
JSON = os.path.join(ROOT, "lab", "results", "design_vs_brute.json")
DOC = os.path.join(ROOT, "docs", "design.md")
BEGIN, END = "<!-- design-vs-brute:begin -->", "<!-- design-vs-brute:end -->"
SCENE = os.path.join(ROOT, "sweeps", "scenes", "paper-hydraulic-dt70.toml")
GRID = 21  # points per for_all axis of the brute force
LATTICE = 65  # points per design range axis: the corners of the 1/64 cells

FORCE = {"metric": "peak_robot_force", "max": 40.0, "abs": True}
SPEED = {"metric": "object_final_velocity", "max": 1.3}
MASS = {"key": "object.mass", "range": [0.05, 1.0]}
DEAD_TIME = {"key": "robot.dead_time", "range": [0.0, 0.1]}
GAS = {"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"}

QUESTIONS = {
    # the notebook's: which gas pressure and orifice, for every mass and dead time
    "gas pressure x orifice": {
        "design": [GAS, {"key": "hydraulic.orifice_radius", "range": [0.002, 0.012]}],
        "for_all": [MASS, DEAD_TIME],
        "limit": [FORCE, SPEED],
    },
    # a list design key: how fast may the robot approach, with either module
    "module x approach speed": {
        "design": [{"key": "module", "values": ["hydraulic", "bistable"]},
                   {"key": "robot.approach_speed", "range": [0.3, 1.5]}],
        "for_all": [MASS, DEAD_TIME],
        "limit": [FORCE, SPEED],
    },
    # the dead time as a design axis: the longest dead time each gas pressure allows (with an
    # 8.5 mm orifice, inside the first question's feasible band)
    "gas pressure x dead time": {
        "set": {"hydraulic.orifice_radius": 0.0085},
        "design": [GAS, {"key": "robot.dead_time", "range": [0.0, 0.1]}],
        "for_all": [MASS, {"key": "robot.approach_speed", "range": [0.5, 1.0]}],
        "limit": [FORCE, SPEED],
    },
}


def question(name: str) -> dict:
    q = dict(QUESTIONS[name])
    q.update({"name": re.sub(r"\W+", "-", name), "scene": SCENE, "set": {"solver.rtol": 1e-6, **q.get("set", {})}})
    return q


def lattice(axis: dict, n: int) -> list:
    if "values" in axis:
        return list(axis["values"])
    lo, hi = axis["range"]
    if axis.get("scale") == "log":
        v = np.exp(np.linspace(math.log(lo), math.log(hi), n))
    else:
        v = np.linspace(lo, hi, n)
    # the ends exactly (exp(log(lo)) may round below lo, outside the design box)
    return list(np.clip(v, lo, hi))


def worst_of(frame: pd.DataFrame, limit: dict) -> pd.Series:
    v = frame[limit["metric"]]
    if limit.get("abs"):
        return v.abs()
    return v


# Committed: the brute force costs about 20 minutes on 2 cores and does not change when the
# search does (only when the model's numbers do: then delete the folder).
CACHE = os.environ.get("CUSHION_BRUTE_CACHE", os.path.join(ROOT, "lab", "results", "design_brute"))


def brute(q: dict, threads: int) -> tuple[pd.DataFrame, int, float]:
    """Per lattice design point: the worst case of each limit over the for_all grid, its margin.
    Kept in $CUSHION_BRUTE_CACHE (default lab/results/design_brute/), keyed by the question."""
    import hashlib

    portable = {**q, "scene": os.path.relpath(q["scene"], ROOT)}  # the same key in any clone
    key = hashlib.sha256(json.dumps(portable, sort_keys=True).encode()).hexdigest()[:12]
    path = os.path.join(CACHE, f"{q['name']}-{key}.parquet")
    if os.path.exists(path):
        worst = pd.read_parquet(path)
        return worst, int(worst.attrs.get("runs", 0)) or int(json.load(open(path + ".json"))["runs"]), float(json.load(open(path + ".json"))["wall"])
    worst, runs, wall = _brute(q, threads)
    os.makedirs(CACHE, exist_ok=True)
    worst.to_parquet(path)
    json.dump({"runs": runs, "wall": wall}, open(path + ".json", "w"))
    return worst, runs, wall


def _brute(q: dict, threads: int) -> tuple[pd.DataFrame, int, float]:
    import cushion

    axes = [{"key": a["key"], "values": lattice(a, LATTICE)} for a in q["design"]]
    axes += [{"key": a["key"], "values": lattice(a, GRID)} for a in q["for_all"]]
    start = time.perf_counter()
    runs = cushion.sweep(
        {"name": "brute", "scene": q["scene"], "set": q["set"], "sampling": {"mode": "grid"}, "axis": axes},
        threads=threads,
        progress=False,
    )
    wall = time.perf_counter() - start
    keys = [a["key"] for a in q["design"]]
    ok = runs["status"] == "ok"
    cols = {}
    for lim in q["limit"]:
        w = worst_of(runs, lim).where(ok, np.inf)
        cols[lim["metric"]] = w
    frame = pd.DataFrame({**{k: runs[k] for k in keys}, **cols})
    worst = frame.groupby(keys, sort=False).max().reset_index()
    margins = [(lim["max"] - worst[lim["metric"]]) / abs(lim["max"]) for lim in q["limit"]]
    worst["margin"] = np.minimum.reduce(margins)
    return worst, len(runs), wall


def lattice_index(frame: pd.DataFrame, axes: list[dict]) -> pd.DataFrame:
    """`frame` with a column `<key>.i` per design axis: the point's index on the lattice (the
    value of a list axis as it is), NaN off the lattice. Matching by index, not by value, as a
    log axis's lattice values are computed two ways and agree only to a few ulps."""
    out = frame.copy()
    for a in axes:
        k = a["key"]
        if "values" in a:
            out[f"{k}.i"] = out[k]
            continue
        lo, hi = a["range"]
        v = out[k].to_numpy(dtype=float)
        u = (np.log(v / lo) / math.log(hi / lo)) if a.get("scale") == "log" else (v - lo) / (hi - lo)
        i = np.round(u * (LATTICE - 1))
        out[f"{k}.i"] = np.where(np.abs(u * (LATTICE - 1) - i) < 1e-6, i, np.nan)
    return out


def compare(name: str, threads: int) -> dict:
    import cushion

    q = question(name)
    start = time.perf_counter()
    answer = cushion.design(q, threads=threads, progress=False)
    search_wall = time.perf_counter() - start
    bf, bf_runs, bf_wall = brute(q, threads)
    keys = [a["key"] for a in q["design"]]
    # classification where the brute force is clear by more than 1 %
    clear = bf[bf["margin"].abs() > 0.01]
    inside = clear[keys].copy()
    for a in q["design"]:
        if "range" in a:  # a brute force cached before the ends were clipped
            inside[a["key"]] = inside[a["key"]].clip(*a["range"])
    feasible = answer.classify(inside)
    disagree = int((feasible.to_numpy() != (clear["margin"] > 0).to_numpy()).sum())
    # the search's worst cases at its design points against the brute force's there
    pts = answer.points
    below, above, compared = [], [], 0
    for lim in q["limit"]:
        m = lim["metric"]
        found = pts[f"{m}.worst"].abs() if lim.get("abs") else pts[f"{m}.worst"]
        a = lattice_index(pd.DataFrame({**{k: pts[k] for k in keys}, "found": found}), q["design"])
        b = lattice_index(bf[keys + [m]], q["design"])
        idx = [f"{k}.i" for k in keys]
        merged = a.dropna(subset=idx).merge(b[idx + [m]], on=idx, how="inner")
        compared += len(merged)
        rel = (merged["found"] - merged[m]) / merged[m].abs()
        below.append(float(max(0.0, -rel.min())) if len(rel) else 0.0)
        above.append(float(rel.max()) if len(rel) else 0.0)
    return {
        "question": name,
        "design_points": len(pts),
        "search_runs": int(answer.best["runs"]["total"]),
        "search_wall_seconds": search_wall,
        "brute_runs": bf_runs,
        "brute_wall_seconds": bf_wall,
        "clear_lattice_points": len(clear),
        "classification_disagreements": disagree,
        "points_compared": compared,
        "largest_shortfall": max(below),
        "largest_excess": max(above),
        "chosen": answer.best["design"],
        "verified": bool(answer.best["verification"]["all_met"]),
        "margin": answer.best["margin"],
    }


def table(rows: list[dict]) -> str:
    lines = [
        "| question | search runs (wall time, 2 threads) | brute force runs (wall time) | share | lattice points clear by 1 %: misclassified | worst cases compared: largest shortfall / excess | chosen design, verified |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        chosen = ", ".join(f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}" for k, v in r["chosen"].items())
        lines.append(
            f"| {r['question']} | {r['search_runs']:,} ({r['search_wall_seconds']:.1f} s) | {r['brute_runs']:,} "
            f"({r['brute_wall_seconds']:.0f} s) | {100 * r['search_runs'] / r['brute_runs']:.2f} % | "
            f"{r['classification_disagreements']} of {r['clear_lattice_points']:,} | {r['points_compared']:,}: "
            f"{r['largest_shortfall']:.1e} / {r['largest_excess']:.1e} | {chosen}, margin {r['margin']:.3f}, "
            f"{'yes' if r['verified'] else 'NO'} |"
        )
    return "\n".join(lines)


def write_doc(rows: list[dict]) -> None:
    text = open(DOC).read()
    block = f"{BEGIN}\n<!-- generated by `.venv/bin/python -m lab.design_vs_brute --tables` from lab/results/design_vs_brute.json -->\n{table(rows)}\n{END}"
    if BEGIN not in text:
        raise SystemExit(f"{DOC}: no {BEGIN} marker")
    open(DOC, "w").write(re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: block, text, flags=re.S))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tables", action="store_true")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", help="one question's name")
    args = ap.parse_args()
    if not args.tables:
        rows = []
        for name in QUESTIONS:
            if args.only and name != args.only:
                continue
            r = compare(name, args.threads)
            print(json.dumps(r), file=sys.stderr)
            rows.append(r)
        json.dump(rows, open(JSON, "w"), indent=1)
    rows = json.load(open(JSON))
    if os.path.exists(DOC) and BEGIN in open(DOC).read():
        write_doc(rows)
    print(table(rows))


if __name__ == "__main__":
    main()
