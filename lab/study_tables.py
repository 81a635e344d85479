#!/usr/bin/env python3
"""The work-precision study's tables, as docs/performance.md shows them, from its JSON
(`python3 -m lab.make_docs` writes them into the page).

    python3 -m lab.study_tables [lab/results/work_precision.json]

Reads the interpolated tables `lab/work_precision.py` writes (`at_error`: where the object's
final speed error first crosses each level; `at_error_settled`: where it crosses it for the last
time), and prints, in Markdown: time and evaluations per method at 1e-6 and 1e-9 on hydraulic
dt70; dop853's time over dp5's per scene and level; the engine's fastest explicit method
against the compiled peer and SciPy's RK45 at every level on each scene the peer runs; the
steel stops read both ways; and the issue's targets (`target_lines`, which the study also
prints at the end of its run). Standard library only.
"""

import json
import os
import sys

ENGINE_ON = ("dp5", "dop853")
ENGINE_OFF = ("dp5_no_ledger", "dop853_no_ledger")
COMPILED_PEER = ("cyrk-DOP853", "cyrk-RK45")
LEVELS = ("0.0001", "1e-05", "1e-06", "1e-07", "1e-08", "1e-09")
# names as the tables show them
LABELS = {
    "dp5": "cushion dp5", "dop853": "cushion dop853", "dp5_no_ledger": "cushion dp5, ledger off",
    "dop853_no_ledger": "cushion dop853, ledger off", "dp5_no_tail": "cushion dp5, ringing tail off",
    "auto": "cushion auto", "rodas": "cushion rodas", "rk4": "cushion rk4", "euler": "cushion euler",
    "cyrk-DOP853": "CyRK DOP853, numba right-hand side", "cyrk-RK45": "CyRK RK45, numba right-hand side",
    "hairer-dopri5": "Hairer's DOPRI5 (Fortran, `scipy.integrate.ode`)",
    "hairer-dop853": "Hairer's DOP853 (Fortran, `scipy.integrate.ode`)",
    "RK45": "SciPy RK45", "DOP853": "SciPy DOP853", "LSODA": "SciPy LSODA", "Radau": "SciPy Radau",
}
# the method in a table's cell, where its column already says whose or which variant it is
SHORT = {"cyrk-DOP853": "DOP853", "cyrk-RK45": "RK45", "dp5_no_ledger": "dp5", "dop853_no_ledger": "dop853"}


def level_name(level):
    """'1e-06' -> '1e-6'."""
    mantissa, _, exponent = f"{float(level):.0e}".partition("e")
    return f"{mantissa}e{int(exponent)}"


def duration(seconds, least_ms=0.01):
    """µs below `least_ms` seconds, ms above."""
    if seconds < least_ms:
        return f"{seconds * 1e6:,.0f} µs"
    ms = seconds * 1e3
    return f"{ms:,.1f} ms" if ms < 1000 else f"{ms:,.0f} ms"


def fastest(row, methods, level):
    """The fastest of `methods` at `level` in one scene's interpolated table: (seconds, method),
    or None where none reaches it."""
    found = [(row[m][level][0], m) for m in methods if m in row and row[m].get(level) is not None]
    return min(found) if found else None


def cell(row, methods, level):
    """The fastest of `methods` at `level` as a table cell: '-' where the scene ran none of them."""
    if not any(m in row for m in methods):
        return "-"
    found = fastest(row, methods, level)
    if found is None:
        return "not reached"
    seconds, method = found
    return f"{duration(seconds)} ({SHORT.get(method, method)})"


def peer_scenes(table):
    return [name for name, row in table.items() if any(m in row for m in COMPILED_PEER)]


def dt70_table(table):
    row = table["paper-hydraulic-dt70"]
    lines = ["| method | error 1e-6 | error 1e-9 |", "|---|---|---|"]
    for m, r in row.items():
        if m in ("rk4", "euler"):  # fixed steps: charted, not read at a level here
            continue
        cells = ["not reached" if r.get(k) is None else f"{duration(r[k][0])}, {r[k][1]:,.0f}"
                 for k in ("1e-06", "1e-09")]
        lines.append(f"| {LABELS.get(m, m)} | {cells[0]} | {cells[1]} |")
    return lines


def peer_table(table):
    lines = ["| scene | error | cushion, ledger on | ledger off | CyRK + numba | SciPy RK45 |",
             "|---|---|---|---|---|---|"]
    for name in peer_scenes(table):
        row = table[name]
        for level in LEVELS:
            if not any(row.get(m, {}).get(level) for m in ENGINE_ON + COMPILED_PEER):
                continue
            rk45 = row.get("RK45", {}).get(level)
            lines.append(f"| {name} | {level_name(level)} | {cell(row, ENGINE_ON, level)} | "
                         f"{cell(row, ENGINE_OFF, level)} | {cell(row, COMPILED_PEER, level)} | "
                         f"{'not reached' if rk45 is None else duration(rk45[0], least_ms=0.0)} |")
    return lines


def order_table(table):
    """dop853's time over dp5's at each level, per scene that runs both (first crossing)."""
    lines = ["| scene | " + " | ".join(level_name(k) for k in LEVELS) + " |",
             "|---|" + "---|" * len(LEVELS)]
    for name, row in table.items():
        if "dp5" not in row or "dop853" not in row:
            continue
        cells = []
        for level in LEVELS:
            a, b = row["dop853"].get(level), row["dp5"].get(level)
            cells.append("-" if a is None or b is None else f"{a[0] / b[0]:.2f}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines


def two_readings(table, settled, name):
    """First crossing / settled, per level, for one scene."""
    lines = ["| error | cushion, ledger on | ledger off | CyRK + numba |", "|---|---|---|---|"]
    for level in LEVELS:
        cells = []
        for methods in (ENGINE_ON, ENGINE_OFF, COMPILED_PEER):
            cells.append(f"{cell(table[name], methods, level)} / {cell(settled[name], methods, level)}")
        lines.append(f"| {level_name(level)} | " + " | ".join(cells) + " |")
    return lines


def target_lines(table, table_settled):
    """The issue's speed targets read off the interpolated tables, as lines to print: the engine
    against SciPy's RK45 and Hairer's DOPRI5 at an error of 1e-6 on hydraulic dt70, and its
    fastest explicit method against the compiled peer's faster one at every level (first
    crossing; where the error stays below, in brackets)."""
    lines = []
    dt70 = table.get("paper-hydraulic-dt70", {})
    rk45, best = fastest(dt70, ("RK45",), "1e-06"), fastest(dt70, ENGINE_ON, "1e-06")
    dp5 = fastest(dt70, ("dp5",), "1e-06")
    if rk45 and best and dp5:
        lines.append(f"SciPy RK45 over the engine at 1e-6, hydraulic dt70: {rk45[0] / best[0]:.0f} times "
                     f"({best[1]}), {rk45[0] / dp5[0]:.0f} times (dp5); target 500")
    hairer = dt70.get("hairer-dopri5", {}).get("1e-06")
    if hairer and dp5:
        lines.append(f"evaluations at 1e-6, hydraulic dt70: dp5 {dt70['dp5']['1e-06'][1]:.0f}, "
                     f"Hairer's DOPRI5 {hairer[1]:.0f}; target: no more")
    for name in table:
        if not any(m in table[name] for m in COMPILED_PEER):
            continue
        for level in table[name]["dp5"]:
            cells = []
            for t in (table, table_settled):
                peer = fastest(t[name], COMPILED_PEER, level)
                on, off = fastest(t[name], ENGINE_ON, level), fastest(t[name], ENGINE_OFF, level)
                if peer is None or on is None:
                    cells.append("-")
                    continue
                ratio = lambda e: "-" if e is None else f"{e[0] / peer[0]:.2f}"
                cells.append(f"{on[0] * 1e6:.0f} us ({on[1]}) / {peer[0] * 1e6:.0f} us ({peer[1]}) = "
                             f"{ratio(on)}, ledger off {ratio(off)}")
            lines.append(f"{name} {level}: {cells[0]}   [{cells[1]}]")
    return lines


def load(path):
    """The study's JSON, its `at_error` and its `at_error_settled` tables."""
    with open(path) as f:
        study = json.load(f)
    return study, study["at_error"], study["at_error_settled"]


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results",
                                                               "work_precision.json")
    study, table, settled = load(path)
    print(f"{study.get('Model name', '?')}, commit {study['git_commit'][:7]}, {study['date']}\n")
    if "paper-hydraulic-dt70" in table:
        print("paper-hydraulic-dt70, object final speed: time per run and evaluations\n")
        print("\n".join(dt70_table(table)) + "\n")
    print("dop853's time over dp5's, first crossing\n")
    print("\n".join(order_table(table)) + "\n")
    print("The engine's fastest explicit method against the compiled peer's, first crossing\n")
    print("\n".join(peer_table(table)) + "\n")
    if "steel-stops" in table:
        print("steel-stops, first crossing / settled\n")
        print("\n".join(two_readings(table, settled, "steel-stops")) + "\n")
    print("Against the targets (engine time over the compiled peer's: below 1 is ahead; "
          "first crossing, [where the error stays below]):")
    for line in target_lines(table, settled):
        print("  " + line)


if __name__ == "__main__":
    main()
