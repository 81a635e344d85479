#!/usr/bin/env python3
"""The steel stops over an ensemble of dead times: the engine against the compiled peer where
neither can draw a lucky error.

    .venv/bin/python -m lab.steel_ensemble [--dead-times MS ...] [--quick] [--out DIR]
    .venv/bin/python -m lab.steel_ensemble --tables   # docs/performance.md's table from the results

On one scene the steel stops' final-speed error jumps about from one tolerance to the next, for
the engine and for CyRK alike: it is the phase of the tool-object ringing as the contact opens
at 79.6 ms (docs/performance.md, "The steel stops: two readings"), so where one method's error
first crosses a level says which method drew well near it. Here the same scene (the paper's
hydraulic scene with `stops.stiffness = 1e11`) runs at several robot dead times (30 to 100 ms
by default: the sensor, the brake and so the contact's opening move), each a draw of its own;
at every tolerance the errors are summarised over the ensemble (the median and the largest) and
the work is averaged (mean time per run, mean evaluations). The levels are then read off those
curves as work_precision.py reads one scene's: where the median error first crosses each level,
and where it crosses it for the last time.

Everything else is work_precision.py's (imported): the references (the engine's dp5 at rtol
1e-13 and SciPy's DOP853 at the same tolerance on the Python model, each run against its own
model's reference, errors below ten times their disagreement not resolved), the interleaved
timing (five rounds, the smallest of the rounds' medians), the peer (CyRK's DOP853 and RK45 with
a numba right-hand side). Methods: the engine's dp5, dop853 and dp5 with the ledger off, and the
peer's two, at quarter decades of rtol from 1e-3 to 1e-7 and at 1e-8 and 1e-9, atol = rtol /
1000. About 12 minutes on the 2-vCPU AMD VM. Writes DIR/steel_ensemble.csv (one row per dead
time, method and rtol), prints the study's figures, and rewrites docs/performance.md's
`steel-ensemble` block from the file (as `--tables` and `python3 -m lab.make_docs` do).
"""

import argparse
import math
import os
import sys
import time

import numpy as np

from lab import work_precision as wp  # noqa: E402

OURS = ("dp5", "dop853", "dp5_no_ledger")
PEERS = ("cyrk-DOP853", "cyrk-RK45")
LEVELS = tuple(10.0 ** -k for k in range(4, 10))
MEASURE = "object_final_velocity"


def grid(quick):
    if quick:
        return [1e-3, 1e-5, 1e-7]
    return [10.0 ** (-3 - k / 4) for k in range(17)] + [1e-8, 1e-9]


def scene_name(ms):
    return f"steel-dt{ms}"


def register(dead_times_ms):
    """The ensemble's scenes in work_precision's table: the engine's overrides and the Python
    model with the same dead time."""
    for ms in dead_times_ms:
        d = ms / 1000.0
        wp.SCENES[scene_name(ms)] = (wp.DT70, {"stops.stiffness": 1e11, "robot.dead_time": d},
                                     (wp.sts.Steel, d), False)


def run_scene(name, ref, rtols, args):
    """Every method at every rtol on one scene, timed interleaved: rows of dicts."""
    points = []
    for method in OURS:
        for r in rtols:
            points.append((method, r, wp.engine_point(name, method, dict(rtol=r, atol=r / 1000), args)))
    for method in PEERS:
        for r in rtols:
            points.append((method, r, wp.peer_point(name, method, r, args)))
    wp.time_interleaved([res for *_, res in points], args)
    rows = []
    for method, r, res in points:
        family = "peer" if method in PEERS else "cushion"
        truth = ref["peers" if family == "peer" else "engine"][MEASURE]
        ok = res["status"] == "ok"
        err = abs(res["values"][MEASURE] - truth) if ok else float("nan")
        rows.append(dict(scene=name, method=method, family=family, rtol=r, status=res["status"], error=err,
                         floor=ref["floor"][MEASURE], seconds=res.get("seconds", float("nan")),
                         rhs_evals=res.get("rhs_evals", -1)))
    return rows


def ensemble(df):
    """Per method and rtol, over the dead times: the median and largest error, the mean time
    and evaluations, as a frame `wp.interpolate` reads (scene "ensemble", `error` the median)."""
    import pandas as pd
    out = []
    for (method, rtol), g in df.groupby(["method", "rtol"], sort=False):
        if (g.status != "ok").any():
            continue
        med = float(np.median(g.error))
        out.append(dict(scene="ensemble", method=method, rtol=rtol, error_measure=MEASURE, status="ok",
                        error=med, largest=float(g.error.max()), resolved=bool(med > g.floor.max()),
                        seconds=float(g.seconds.mean()), rhs_evals=float(g.rhs_evals.mean()), runs=len(g)))
    return pd.DataFrame(out)


def level_cells(table, method):
    return ["-" if table[method].get(t) is None else f"{table[method][t][0] * 1e6:,.0f} µs" for t in LEVELS]


RESULTS = os.path.join(wp.ROOT, "lab", "results", "steel_ensemble.csv")
BLOCK = "steel-ensemble"


def level_table(df):
    """docs/performance.md's table: per method, the mean time per run where the median
    final-speed error over the dead times first crosses each level / stays below it."""
    ens = ensemble(df)
    first = wp.interpolate(ens, "ensemble", LEVELS)
    settled = wp.interpolate(ens, "ensemble", LEVELS, settled=True)
    lines = ["| method | " + " | ".join(f"1e-{round(-math.log10(t))}" for t in LEVELS) + " |",
             "|---|" + "---|" * len(LEVELS)]
    for m in OURS + PEERS:
        if m in first:
            cells = [f"{a} / {b}" for a, b in zip(level_cells(first, m), level_cells(settled, m))]
            lines.append(f"| {wp.LABEL.get(m, m)} | " + " | ".join(cells) + " |")
    lines += ["", "(\"-\": the median never crosses that level on the grid.) The engine's faster method over the "
              "peer's faster (below 1: the engine ahead; \"-\": a side does not get there):",
              "", *ratio_lines(first, settled)]
    return "\n".join(lines)


def ratio_lines(first, settled):
    """The engine's fastest over the peer's fastest at each level, first crossing and settled,
    at the defaults and with the ledger off."""
    def best(table, methods, t):
        c = [table[m][t][0] for m in methods if m in table and table[m].get(t)]
        return min(c) if c else None

    def ratios(table, ours):
        cells = []
        for t in LEVELS:
            a, b = best(table, ours, t), best(table, PEERS, t)
            cells.append("-" if a is None or b is None else f"{a / b:.2f}")
        return ", ".join(cells)

    levels = ", ".join(f"1e-{round(-math.log10(t))}" for t in LEVELS)
    return [f"- at the defaults ({levels}): first crossing {ratios(first, ('dp5', 'dop853'))}; "
            f"settled {ratios(settled, ('dp5', 'dop853'))};",
            f"- with the ledger off: first crossing {ratios(first, ('dp5_no_ledger',))}; "
            f"settled {ratios(settled, ('dp5_no_ledger',))}."]


def write_block(path=RESULTS):
    """Rewrite the `steel-ensemble` block of docs/performance.md from the result file."""
    import pandas as pd
    from lab.make_docs import PERFORMANCE, replace_block
    df = pd.read_csv(path, comment="#")
    return replace_block(PERFORMANCE, BLOCK, level_table(df), "lab/results/steel_ensemble.csv")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dead-times", nargs="+", type=int, default=[30, 40, 50, 60, 70, 80, 90, 100],
                    help="robot dead times, ms")
    ap.add_argument("--quick", action="store_true", help="a smoke run: three tolerances, one round")
    ap.add_argument("--tables", action="store_true", help="only rewrite the docs' table from the results")
    ap.add_argument("--out", default=os.path.join(wp.ROOT, "lab", "results"), help="folder of steel_ensemble.csv")
    args = ap.parse_args()
    if args.tables:
        sys.exit(0 if write_block() else 1)
    args.budget, args.ref_budget, args.peer_slow = 30.0, 300.0, 1.0
    args.target, args.most, args.rounds = (0.05, 3, 1) if args.quick else (0.2, 2000, 5)

    import pandas as pd
    t_start = time.perf_counter()
    register(args.dead_times)
    names = [scene_name(ms) for ms in args.dead_times]
    wp.cyrk_setup()
    if not isinstance(wp.CYRK, wp.cyrk_peer.Peer):
        sys.exit(f"the compiled peer is missing: {wp.CYRK}")
    refs = wp.references(names, args)
    rows = []
    for name in names:
        r = refs[name]
        wp.log(f"  {name}: references {r['A'][1][MEASURE]:.15g} / {r['B'][1][MEASURE]:.15g} m/s, "
               f"|A-B| {abs(r['A'][1][MEASURE] - r['B'][1][MEASURE]):.1e}")
        t0 = time.perf_counter()
        rows += run_scene(name, r, grid(args.quick), args)
        wp.log(f"  {name}: {time.perf_counter() - t0:.0f} s")
    df = pd.DataFrame(rows)
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "steel_ensemble.csv")
    with open(path, "w") as f:
        info = wp.machine_info()
        f.write(f"# lab/steel_ensemble.py: commit {info['git_commit'][:12]}, {info['date']}, "
                f"{info.get('Model name', '?')}, {info['cores']} cores; dead times {args.dead_times} ms\n")
        df.to_csv(f, index=False)
    wp.log(f"wrote {path}")

    ens = ensemble(df)
    first = wp.interpolate(ens, "ensemble", LEVELS)
    settled = wp.interpolate(ens, "ensemble", LEVELS, settled=True)
    wp.log(f"\nsteel stops over {len(names)} dead times: mean time per run where the median final-speed error "
           "first crosses each level / where it stays below it")
    wp.log(level_table(df))
    if not args.quick and os.path.abspath(path) == RESULTS:
        write_block(path)
    wp.log("\nper rtol: median / largest error over the dead times (m/s), mean evaluations, mean µs per run")
    for m in OURS + PEERS:
        g = ens[ens.method == m]
        for _, x in g.iterrows():
            wp.log(f"  {m:14s} rtol {x.rtol:.1e}: {x.error:.1e} / {x.largest:.1e}  {x.rhs_evals:8.0f}  "
                   f"{x.seconds * 1e6:8.0f}")
    wp.log("\nthe engine's fastest over the peer's fastest, first crossing [settled] (below 1: ahead)")
    for t in LEVELS:
        def best(table, methods):
            c = [(table[m][t][0], m) for m in methods if m in table and table[m].get(t)]
            return min(c) if c else None
        for label, table in (("first", first), ("settled", settled)):
            a, b = best(table, ("dp5", "dop853")), best(table, PEERS)
            if a and b:
                wp.log(f"  {t:g} {label}: {a[0] * 1e6:.0f} µs ({a[1]}) / {b[0] * 1e6:.0f} µs ({b[1]}) = "
                       f"{a[0] / b[0]:.2f}")
    wp.log(f"total {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
