"""Whether `auto` costs anything as the default method: every scene of the work-precision study
under `dp5` and `auto` at rtol 1e-3 to 1e-9, the evaluations, the switches and the errors of
the object's final speed and the peak robot force against a reference (`rodas` at rtol 1e-11;
on the non-stiff scenes also `dop853` at 1e-12, the smaller of the two differences is reported
as the reference's own spread).

    .venv/bin/python -m lab.default_method            # runs, writes lab/results/default_method.csv
    .venv/bin/python -m lab.default_method --design-space target/release/cushion
    .venv/bin/python -m lab.default_method --tables   # docs/performance.md's table from the results

`--design-space BIN` runs sweeps/design-space.toml under each method with BIN (a release build),
three times each, alternating, on 2 threads, and compares the two summaries run for run
(lab/results/default_method_design_space.json).

The last column says whether `auto`'s summary equals `dp5`'s field for field (but the implicit
method's counters), or which fields differ."""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CSV = os.path.join(ROOT, "lab", "results", "default_method.csv")
DS_JSON = os.path.join(ROOT, "lab", "results", "default_method_design_space.json")
DOC = os.path.join(ROOT, "docs", "performance.md")
BEGIN, END = "<!-- default-method:begin -->", "<!-- default-method:end -->"

DT70 = "sweeps/scenes/paper-hydraulic-dt70.toml"
SCENES = {
    "paper-hydraulic-dt70": (DT70, {}),
    "paper-hydraulic-dt10": ("sweeps/scenes/paper-hydraulic-dt10.toml", {}),
    "paper-bistable-dt70": ("sweeps/scenes/paper-bistable-dt70.toml", {}),
    "paper-bistable-dt10": ("sweeps/scenes/paper-bistable-dt10.toml", {}),
    "paper-rigid": ("sweeps/scenes/paper-rigid.toml", {}),
    "steel-stops": (DT70, {"stops.stiffness": 1e11}),
    "compressible": (DT70, {"hydraulic.bulk_modulus": 1.5e9}),
}
RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
METRICS = ["object_final_velocity", "peak_robot_force"]
IGNORED = {"stats_method_switches", "stats_jacobians", "stats_lu_decompositions"}


def flat(summary: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in summary.items():
        if isinstance(v, dict):
            out.update(flat(v, f"{prefix}{k}_"))
        else:
            out[prefix + k] = v
    return out


def run(name: str, method: str, rtol: float) -> dict:
    import cushion

    path, over = SCENES[name]
    s = dict(over)
    s["solver.method"] = method
    s["solver.rtol"] = rtol
    s["solver.atol"] = rtol * 1e-3
    return flat(cushion.simulate(os.path.join(ROOT, path), set=s, trajectory=False).summary)


def same_value(x, y) -> bool:
    return x == y or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y))


def measure() -> list[dict]:
    rows = []
    for name in SCENES:
        ref = run(name, "rodas", 1e-11)
        assert ref["status"] == "ok", (name, ref["message"])
        for rtol in RTOLS:
            a = {m: run(name, m, rtol) for m in ("dp5", "auto")}
            differ = [
                k for k in a["dp5"]
                if k not in IGNORED and not same_value(a["dp5"][k], a["auto"][k])
            ]
            row = {"scene": name, "rtol": rtol, "differs_in": " ".join(differ)}
            for m, r in a.items():
                row[f"{m}_status"] = r["status"]
                row[f"{m}_evaluations"] = r["stats_rhs_evals"]
                row[f"{m}_switches"] = r.get("stats_method_switches", 0)
                for k in METRICS:
                    row[f"{m}_{k}_error"] = abs(r[k] - ref[k]) if r["status"] == "ok" else float("nan")
            rows.append(row)
            print(name, rtol, row["dp5_evaluations"], row["auto_evaluations"], differ, file=sys.stderr)
    return rows


def design_space(binary: str) -> dict:
    import subprocess
    import tempfile

    import pandas as pd

    src = open(os.path.join(ROOT, "sweeps", "design-space.toml")).read()
    scenes = os.path.join(ROOT, "sweeps", "scenes") + "/"
    out: dict = {"wall_seconds": {"dp5": [], "auto": []}}
    with tempfile.TemporaryDirectory() as tmp:
        for m in ("dp5", "auto"):
            text = src.replace('scene = "scenes/', f'scene = "{scenes}')
            text = text.replace('"solver.rtol" = 1e-6', f'"solver.rtol" = 1e-6\n"solver.method" = "{m}"')
            open(os.path.join(tmp, f"{m}.toml"), "w").write(text)
        for _ in range(3):
            for m in ("dp5", "auto"):
                res = subprocess.run(
                    [binary, "sweep", os.path.join(tmp, f"{m}.toml"), "--out", os.path.join(tmp, m), "--threads", "2"],
                    capture_output=True, text=True, check=True,
                )
                out["wall_seconds"][m].append(float(re.search(r"in ([0-9.]+) s", res.stdout).group(1)))
                print(m, res.stdout.strip(), file=sys.stderr)
        a = pd.read_parquet(os.path.join(tmp, "dp5", "summary.parquet"))
        b = pd.read_parquet(os.path.join(tmp, "auto", "summary.parquet"))
    fields = [c for c in a.columns if not c.startswith("stats_")]
    differ = pd.Series(False, index=a.index)
    for c in fields:
        differ |= ~((a[c] == b[c]) | (a[c].isna() & b[c].isna()))
    out["runs"] = len(a)
    out["runs_switched"] = int((b["stats_method_switches"] > 0).sum())
    out["runs_differing"] = int(differ.sum())
    out["evaluations"] = {"dp5": int(a["stats_rhs_evals"].sum()), "auto": int(b["stats_rhs_evals"].sum())}
    out["largest_difference"] = {
        c: float((a[c] - b[c]).abs().max())
        for c in ("peak_robot_force", "object_final_velocity", "max_stroke", "t_detect")
    }
    return out


def design_space_text(d: dict) -> str:
    w = d["wall_seconds"]
    ev = d["evaluations"]
    big = d["largest_difference"]
    return (
        f"`sweeps/design-space.toml` ({d['runs']:,} runs, rtol 1e-6) under each, with a release build, "
        f"three times each, alternating, `--threads 2`: `dp5` {min(w['dp5']):.2f}-{max(w['dp5']):.2f} s, "
        f"`auto` {min(w['auto']):.2f}-{max(w['auto']):.2f} s. `auto` switches to Rodas in "
        f"{d['runs_switched']:,} runs (a small orifice's overdamped mode, a tool resting on its stop); "
        f"{d['runs_differing']:,} runs give other numbers than under `dp5`, within the tolerance: at most "
        f"{big['object_final_velocity']:.1e} m/s in the object's final speed, {big['max_stroke']:.1e} m in the "
        f"stroke, {big['t_detect']:.1e} s in the detection time, {big['peak_robot_force']:.1e} N in the peak "
        f"robot force; {100 * (ev['auto'] / ev['dp5'] - 1):+.1f} % evaluations."
    )


def fmt_e(x: float) -> str:
    return "-" if x != x else f"{x:.1e}"


def table(rows: list[dict]) -> str:
    lines = [
        "| scene | rtol | dp5 evaluations | auto evaluations | auto switches | final speed error, dp5 / auto (m/s) | peak force error, dp5 / auto (N) | auto's summary |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        def ev(m):
            e = r[f"{m}_evaluations"]
            st = r[f"{m}_status"]
            return f"{int(float(e)):,}" + ("" if st == "ok" else f" ({st})")
        differ = r["differs_in"].split()
        if not differ:
            same = "dp5's, to the bit"
        elif differ == ["stats_stiff"]:
            same = "dp5's numbers to the bit; `stats.stiff` false (dp5's test fired, auto did not switch)"
        else:
            same = "auto's own run"
        lines.append(
            f"| {r['scene']} | {float(r['rtol']):.0e} | {ev('dp5')} | {ev('auto')} | {r['auto_switches']} | "
            f"{fmt_e(float(r['dp5_object_final_velocity_error']))} / {fmt_e(float(r['auto_object_final_velocity_error']))} | "
            f"{fmt_e(float(r['dp5_peak_robot_force_error']))} / {fmt_e(float(r['auto_peak_robot_force_error']))} | {same} |"
        )
    return "\n".join(lines)


def write_doc(rows: list[dict], ds: dict | None) -> None:
    text = open(DOC).read()
    body = table(rows) + ("" if ds is None else "\n\n" + design_space_text(ds))
    block = f"{BEGIN}\n<!-- generated by `.venv/bin/python -m lab.default_method --tables` from lab/results/default_method*.csv/json -->\n{body}\n{END}"
    if BEGIN in text:
        text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: block, text, flags=re.S)
    else:
        raise SystemExit(f"{DOC}: no {BEGIN} marker to write the table at")
    open(DOC, "w").write(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tables", action="store_true", help="only regenerate the docs' table from the results")
    ap.add_argument("--design-space", metavar="BIN", help="only time and compare the design space with BIN")
    args = ap.parse_args()
    if args.design_space:
        with open(DS_JSON, "w") as f:
            json.dump(design_space(args.design_space), f, indent=1)
    elif not args.tables:
        rows = measure()
        with open(CSV, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    with open(CSV) as f:
        rows = list(csv.DictReader(f))
    ds = json.load(open(DS_JSON)) if os.path.exists(DS_JSON) else None
    write_doc(rows, ds)
    print(table(rows))


if __name__ == "__main__":
    main()
