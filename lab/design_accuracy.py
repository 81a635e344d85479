"""Accuracy of the design-space sweep at its tolerance (rtol 1e-6) against the same 16,384 runs
at rtol 1e-10: per summary field, the median, 99th percentile and largest error (relative;
absolute in N s and m/s for the impulse and the object's speed), the run with the largest, and
how many runs are off by more than 1e-4; the statuses and the mean evaluations per run. A
benchmark, not a test.

    python3 -m lab.design_accuracy                  # two sweeps, about 10 s after the release build
    python3 -m lab.design_accuracy KEY=VALUE ...    # other settings of the runs (the reference
                                                    # stays at rtol 1e-10); prints, writes nothing
    python3 -m lab.design_accuracy --tables         # docs/accuracy.md's block from the results

Writes lab/results/design_accuracy.json (at the sweep's own settings, and the variants of
`VARIANTS`: DOP853 and DOPRI5 at several tolerances); the blocks `design-accuracy` and
`design-accuracy-methods` of docs/accuracy.md are drawn from it (here and by
`python3 -m lab.make_docs`).
"""

import csv
import json
import os
import re
import subprocess
import sys
import tempfile

from lab import study as lab
from lab.study import sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = lab.binary("cushion")
RESULTS = os.path.join(ROOT, "lab", "results", "design_accuracy.json")
ACCURACY = os.path.join(ROOT, "docs", "accuracy.md")
# The methods compared on the design space (docs/accuracy.md, section 7).
VARIANTS = [{"solver.method": m, "solver.rtol": r}
            for m, r in [("dop853", "1e-6"), ("dop853", "1e-7"), ("dop853", "1e-8"), ("dp5", "1e-6"), ("dp5", "1e-8")]]
FIELDS = {  # field: (label, absolute error?)
    "peak_robot_force": ("peak robot force (rel)", False),
    "peak_contact_force": ("peak contact force (rel)", False),
    "max_stroke": ("max stroke (rel)", False),
    "max_gas_pressure": ("max gas pressure (rel)", False),
    "robot_impulse": ("robot impulse (N s)", True),
    "object_final_velocity": ("object final speed (m/s)", True),
}


def summary(tmp, name, sets):
    out = os.path.join(tmp, name)
    subprocess.run([CLI, "sweep", lab.design_space_file(tmp, name, sets), "--out", out, "--quiet"], check=True)
    with open(os.path.join(out, "summary.csv")) as f:
        return list(csv.DictReader(f))


def toml_value(v):
    return v if re.fullmatch(r"[-+0-9.eE]+|true|false", v) else json.dumps(v)


def errors(ref, run):
    """Per field: median, 99th percentile, largest error (with its run and value), runs above 1e-4."""
    fields = {}
    for k, (_, absolute) in FIELDS.items():
        errs = []
        for r, x in zip(ref, run):
            if r[k] in ("", "null"):
                continue
            a, b = float(r[k]), float(x[k])
            errs.append((abs(a - b) / (1.0 if absolute else max(abs(a), 1e-300)), int(x["run"]), b))
        errs.sort()
        n = len(errs)
        fields[k] = {"median": errs[n // 2][0], "p99": errs[int(0.99 * n)][0], "largest": errs[-1][0],
                     "largest_run": errs[-1][1], "largest_value": errs[-1][2],
                     "above_1e-4": sum(e > 1e-4 for e, _, _ in errs)}
    return fields


def describe(run):
    residuals = sorted(float(x["energy_residual"]) for x in run if x["energy_residual"] not in ("", "null"))
    statuses = {}
    for x in run:
        statuses[x["status"]] = statuses.get(x["status"], 0) + 1
    return {"runs": len(run), "statuses": statuses,
            "rhs_evals_mean": sum(int(x["stats_rhs_evals"]) for x in run) / len(run),
            "energy_residual": {"median": residuals[len(residuals) // 2], "largest": residuals[-1]}}


def compare(settings, variants=()):
    """The sweep at `settings` against rtol 1e-10, and each of `variants` (settings) against the
    same reference."""
    with tempfile.TemporaryDirectory() as tmp:
        ref = summary(tmp, "reference", {"solver.rtol": "1e-10"})
        run = summary(tmp, "run", {k: toml_value(v) for k, v in settings.items()})
        study = {"settings": settings, **describe(run), "fields": errors(ref, run), "variants": []}
        for i, v in enumerate(variants):
            other = summary(tmp, f"variant-{i}", {k: toml_value(x) for k, x in v.items()})
            study["variants"].append({"settings": v, **describe(other), "fields": errors(ref, other)})
    return study


def table(study):
    ok = study["statuses"].get("ok", 0)
    out = [f"{study['runs']:,} runs, {ok:,} of them `ok`; {study['rhs_evals_mean']:,.0f} evaluations a run on average.", "",
           "| field | median | 99th percentile | largest (run, its value) | runs above 1e-4 |",
           "|---|---|---|---|---|"]
    for k, (label, _) in FIELDS.items():
        f = study["fields"][k]
        out.append(f"| {label} | {sci(f['median'])} | {sci(f['p99'])} | {sci(f['largest'])} (run {f['largest_run']}, "
                   f"{f['largest_value']:.3g}) | {f['above_1e-4']} |")
    return out


def methods_table(study):
    out = ["| design space | peak robot force (rel): 99th pct / largest | max stroke (rel): 99th pct / largest | "
           "object final speed (m/s): 99th pct / largest | evaluations a run |", "|---|---|---|---|---|"]
    for v in study["variants"]:
        f = v["fields"]
        cell = lambda k: f"{sci(f[k]['p99'])} / {sci(f[k]['largest'])}"
        out.append(f"| `{v['settings']['solver.method']}`, rtol {v['settings']['solver.rtol']} | "
                   f"{cell('peak_robot_force')} | {cell('max_stroke')} | {cell('object_final_velocity')} | "
                   f"{v['rhs_evals_mean']:,.0f} |")
    return out


def measure(args):
    """The sweep's own settings and `VARIANTS`; with KEY=VALUE settings, those alone, printed and
    not kept (the command ends here)."""
    lab.release("cushion")
    settings = dict(s.split("=", 1) for s in args.settings)
    if settings:
        print("\n".join(table(compare(settings))))
        sys.exit(0)
    return compare({}, VARIANTS)


def blocks(study):
    return [(ACCURACY, "design-accuracy", "\n".join(table(study))),
            (ACCURACY, "design-accuracy-methods", "\n".join(methods_table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks,
             options=lambda ap: ap.add_argument("settings", nargs="*", help="KEY=VALUE settings of the runs"))


if __name__ == "__main__":
    main()
