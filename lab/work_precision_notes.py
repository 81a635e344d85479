"""The figures docs/performance.md's work-precision prose quotes, from the study's result files
(lab/results/work_precision.csv and .json, and profile.json for the steel stops' parts), as the
blocks `python3 -m lab.make_docs` writes: what the ledger costs, the steel stops against the
peer, the compressible scene, the oscillator, the trajectory at fixed times and where the engine
is behind. Standard library only.
"""

import csv
import json
import os

from lab import study_tables
from lab.study import sci

RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")
FINAL = "object_final_velocity"
TRAJECTORY = "trajectory_velocity"


def rows():
    """The study's CSV as {(scene, method, setting, measure): row}."""
    with open(os.path.join(RESULTS, "work_precision.csv")) as f:
        lines = [line for line in f if not line.startswith("#")]
    return {(r["scene"], r["method"], r["setting"], r["error_measure"]): r for r in csv.DictReader(lines)}


def us(seconds):
    return f"{float(seconds) * 1e6:,.0f} µs"


def ns_per_evaluation(row):
    return float(row["seconds"]) / float(row["rhs_evals"]) * 1e9


def ratios(table, ours, theirs):
    """The fastest of `ours` over the fastest of `theirs` at each level ('-' where either side
    does not get there)."""
    cells = []
    for level in study_tables.LEVELS:
        a, b = study_tables.fastest(table, ours, level), study_tables.fastest(table, theirs, level)
        cells.append("-" if a is None or b is None else f"{a[0] / b[0]:.2f}")
    return cells


def ledger_block(r):
    on, off = (r[("paper-hydraulic-dt70", m, "rtol=1e-6", FINAL)]["seconds"] for m in ("dp5", "dp5_no_ledger"))
    return (f"The ledger's two states cost a few per cent to a third of a run's time at the same rtol "
            f"(hydraulic dt70 at rtol 1e-6: {us(on)} against {us(off)}, in the same rounds).")


def steel_block(table, settled):
    """The steel stops' ratios to the peer, and the compressible scene at an error of 1e-6."""
    levels = ", ".join(study_tables.level_name(k) for k in study_tables.LEVELS)
    peer = study_tables.COMPILED_PEER
    s, t = table["steel-stops"], settled["steel-stops"]
    comp = table["compressible"]
    at = lambda m: comp[m]["1e-06"]
    name = {"rodas": "rodas", "auto": "`auto`", "LSODA": "SciPy LSODA", "Radau": "SciPy Radau"}
    parts = [f"{name[m]} {study_tables.duration(at(m)[0])} ({at(m)[1]:,.0f} evaluations)"
             for m in name if comp.get(m, {}).get("1e-06")]
    return "\n".join([
        f"- The engine's fastest over the peer's fastest on the steel stops ({levels}; below 1: the "
        f"engine ahead): first crossing {', '.join(ratios(s, study_tables.ENGINE_ON, peer))}; settled "
        f"{', '.join(ratios(t, study_tables.ENGINE_ON, peer))}; with the ledger off, settled "
        f"{', '.join(ratios(t, study_tables.ENGINE_OFF, peer))}.",
        f"- The compressible scene at an error of 1e-6: {', '.join(parts)}.",
    ])


def oscillator_block(r):
    row = lambda m, rtol: r[("oscillator", m, f"rtol={rtol}", FINAL)]
    dp5, hairer, rk45 = row("dp5", "1e-6"), row("hairer-dopri5", "1e-6"), row("cyrk-RK45", "1e-6")
    ns = ns_per_evaluation
    d853 = [(row("dop853", k), row("cyrk-DOP853", k), row("hairer-dop853", k)) for k in ("1e-6", "1e-9")]
    return (f"`dp5` at rtol 1e-6 takes {int(dp5['rhs_evals']):,} evaluations (Hairer's DOPRI5: "
            f"{int(hairer['rhs_evals']):,}) to an error of {sci(float(dp5['error']))} (Hairer's: "
            f"{sci(float(hairer['error']))}), in {us(dp5['seconds'])} against CyRK RK45's "
            f"{us(rk45['seconds'])} ({ns(dp5):.0f} against {ns(rk45):.0f} ns an evaluation); `dop853` at "
            f"rtol 1e-6 and 1e-9: {us(d853[0][0]['seconds'])} and {us(d853[1][0]['seconds'])} against CyRK "
            f"DOP853's {us(d853[0][1]['seconds'])} and {us(d853[1][1]['seconds'])}, at errors of "
            f"{sci(float(d853[0][0]['error']))} and {sci(float(d853[1][0]['error']))} (Hairer's DOP853: "
            f"{sci(float(d853[0][2]['error']))} and {sci(float(d853[1][2]['error']))}).")


TRAJECTORY_SCENES = ("paper-hydraulic-dt70", "paper-hydraulic-dt10", "paper-bistable-dt70", "steel-stops")
TRAJECTORY_METHODS = {"dp5": "dp5", "dp5_no_tail": "dp5, ringing tail off", "RK45": "SciPy RK45",
                      "DOP853": "SciPy DOP853", "LSODA": "SciPy LSODA"}


def trajectory_block(r):
    """The largest speed error at the 99 fixed times at rtol 1e-6, and the figures its bullets
    quote."""
    def entry(scene, m, setting="rtol=1e-6"):
        x = r.get((scene, m, setting, TRAJECTORY))
        return x if x and x["status"] == "ok" else None

    def cell(x):
        return "" if x is None else f"{sci(float(x['error']))}, {study_tables.duration(float(x['seconds']))}"

    lines = ["| scene | " + " | ".join(TRAJECTORY_METHODS.values()) + " |",
             "|---|" + "---|" * len(TRAJECTORY_METHODS)]
    for scene in TRAJECTORY_SCENES:
        lines.append(f"| {scene} | " + " | ".join(cell(entry(scene, m)) for m in TRAJECTORY_METHODS) + " |")
    tail, whole = (float(entry("paper-hydraulic-dt70", m)["error"]) for m in ("dp5", "dp5_no_tail"))
    tight, rodas = entry("steel-stops", "dp5", "rtol=1e-10"), entry("steel-stops", "rodas")
    lines += ["", f"On hydraulic dt70 the ringing tail's trajectory is off by {sci(tail)} m/s, {tail / whole:.0f} "
              f"times the integrated run's error. On the steel stops dp5 at rtol 1e-10 gets to {cell(tight)}; "
              f"Rodas at rtol 1e-6 to {cell(rodas)}."]
    return "\n".join(lines)


def behind_block(r, table):
    """The figures of "Where the engine is behind"."""
    steel = lambda m: r[("steel-stops", m, "rtol=1e-6", FINAL)]
    ns = ns_per_evaluation
    ours = [ns(steel(m)) for m in ("dp5", "dop853")]
    with open(os.path.join(RESULTS, "profile.json")) as f:
        case = next(c for c in json.load(f)["cases"] if c["label"].startswith("steel stops"))
    watch = case["parts"]["events"] + case["parts"]["observers"]
    s, peer = table["steel-stops"], study_tables.COMPILED_PEER
    need = [1 / float(x) for x in ratios(s, study_tables.ENGINE_ON, peer)[1:3]]
    dt70 = table["paper-hydraulic-dt70"]
    tight = []
    for level in ("1e-08", "1e-09"):
        a, b = (study_tables.fastest(dt70, m, level) for m in (study_tables.ENGINE_ON, peer))
        tight.append(f"{study_tables.level_name(level)}: {us(a[0])} against {us(b[0])}")
    return "\n".join([
        f"- Steel stops at rtol 1e-6: the engine's dp5 takes {int(steel('dp5')['rhs_evals']):,} evaluations, "
        f"CyRK DOP853 {int(steel('cyrk-DOP853')['rhs_evals']):,}; an evaluation costs the engine "
        f"{min(ours):.0f}-{max(ours):.0f} ns in all (dp5, dop853), the peer's DOP853 "
        f"{ns(steel('cyrk-DOP853')):.0f}. Events and observers take {100 * watch:.0f} % of the scene's "
        f"instructions. To lead at errors of 1e-5 and 1e-6 (first crossing) an evaluation would have to "
        f"cost {need[0]:.2f} and {need[1]:.2f} of what it does.",
        f"- Hydraulic dt70 at tight tolerances, the engine's fastest against the peer's: {'; '.join(tight)}.",
    ])


def blocks():
    """{block name: body} for docs/performance.md."""
    r = rows()
    _, table, settled = study_tables.load(os.path.join(RESULTS, "work_precision.json"))
    return {
        "work-precision-ledger": ledger_block(r),
        "work-precision-steel-notes": steel_block(table, settled),
        "work-precision-oscillator": oscillator_block(r),
        "work-precision-trajectory": trajectory_block(r),
        "engine-behind": behind_block(r, table),
    }


if __name__ == "__main__":
    for name, body in blocks().items():
        print(f"{name}:\n{body}\n")
