"""Every generated block in docs/, from the committed result files in lab/results/.

    python3 -m lab.make_docs          # from the repository root; runs no study

A generated block is the text between `<!-- NAME:begin -->` and `<!-- NAME:end -->` in a page
of docs/; this command rewrites each from its result file, so no figure in those blocks is ever
copied by hand. It writes:

- docs/performance.md, `work-precision-dt70`, `work-precision-peer`, `work-precision-order`,
  `work-precision-steel`: the work-precision study's tables (lab/study_tables.py) from
  lab/results/work_precision.json; `work-precision-ledger`, `-steel-notes`, `-oscillator`,
  `-trajectory` and `engine-behind`: the figures its prose quotes (lab/work_precision_notes.py)
  from lab/results/work_precision.csv and .json and profile.json;
- docs/performance.md, `default-method`: `default_method.py --tables` from
  lab/results/default_method*.csv/json;
- docs/design.md, `design-vs-brute`: `design_vs_brute.py --tables` from
  lab/results/design_vs_brute.json;
- docs/performance.md, `sensitivity-speed`: `sensitivity_speed.py --tables` from
  lab/results/sensitivity_speed.json;
- docs/performance.md, `steel-ensemble`: `steel_ensemble.py --tables` from
  lab/results/steel_ensemble.csv;
- docs/stability.md's generated part and docs/figures/stability-*.svg: `stability_map.py
  --tables` from lab/results/stability_map.json;
- docs/performance.md, `run-time-parts`: `profile.py --tables` from lab/results/profile.json;
- docs/fidelity.md and docs/figures/fidelity.svg (the whole page): `fidelity.py --tables` from
  lab/results/fidelity.csv;
- docs/accuracy.md, `scene-tolerances-errors`, and docs/performance.md,
  `scene-tolerances-cost`: `scene_tolerances.py --tables` from
  lab/results/scene_tolerances.json;
- docs/performance.md, `ringing-tail`: `ringing_tail.py --tables` from
  lab/results/ringing_tail.json;
- docs/performance.md, `paper-scenes` and `against-scipy`: `paper_scenes.py --tables` from
  lab/results/paper_scenes.json (and scene_tolerances.json for the engine's side);
- docs/performance.md, `options-cost`: `options_cost.py --tables` from
  lab/results/options_cost.json;
- docs/performance.md, `design-space-sweep`: `sweep_bench.py --tables` from
  lab/results/sweep_bench.json.

- docs/performance.md, `design-phases`: `design_phases.py --tables` from
  lab/results/design_phases.json;
- docs/performance.md, `python-overhead` and `python-sweep`: `python_overhead.py --tables`
  from lab/results/python_overhead.json;
- docs/accuracy.md, `design-accuracy`: `design_accuracy.py --tables` from
  lab/results/design_accuracy.json;
- docs/accuracy.md, `options-accuracy`: `options_accuracy.py --tables` from
  lab/results/options_accuracy.json;
- docs/integrator.md, `arenstorf`: `arenstorf.py --tables` from lab/results/arenstorf.json;
- docs/integrator.md, `stiff-ode`: `stiff_ode.py --tables` from lab/results/stiff_ode.json;
- docs/accuracy.md, `wide-accuracy`: `wide_accuracy.py --tables` from
  lab/results/wide_accuracy.json;
- docs/accuracy.md, `ringing-tail-check`: `ringing_tail_check.py --tables` from
  lab/results/ringing_tail_check.json;
- docs/accuracy.md, `wide-trajectories`: `wide_trajectories.py --tables` from
  lab/results/wide_trajectories.json;
- docs/performance.md, `stiff-scenes` and `stiff-scenes-scipy`: `stiff_scenes.py --tables`
  from lab/results/stiff_scenes.json;
- docs/accuracy.md, `energy-ledger`: the residuals of the paper scenes and the design space,
  from lab/results/ringing_tail.json and design_accuracy.json;
- docs/performance.md, `in-short`: the page's summary, from lab/results/paper_scenes.json,
  work_precision.json, sweep_bench.json and profile.json.

The studies' own blocks are the studies' own `--tables` modes, run with .venv/bin/python when it exists
(else this interpreter). Exits with status 1 if a block's markers or a study's table could not
be written. `--skip NAME ...` leaves blocks alone
(`in-short`, `energy-ledger`, `work-precision`, `default-method`, `design-vs-brute`, `sensitivity-speed`,
`steel-ensemble`, `stability-map`, `run-time-parts`, `fidelity`, `scene-tolerances`, `ringing-tail`, `paper-scenes`, `options-cost`, `design-space-sweep`, `design-phases`, `python-package`, `design-accuracy`, `options-accuracy`, `stiff-ode`, `arenstorf`, `wide-accuracy`, `ringing-tail-check`, `wide-trajectories`, `stiff-scenes`): a study
whose results are being made.
"""

import argparse
import json
import os
import re
import subprocess
import sys

from lab import study_tables, work_precision_notes
from lab.study import sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "lab", "results")
PERFORMANCE = os.path.join(ROOT, "docs", "performance.md")


def replace_block(path, name, body, source):
    """Put `body` between the page's `name` markers, after a line naming its `source`; False
    where the page has no such markers."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    with open(path) as f:
        text = f.read()
    if begin not in text or end not in text:
        print(f"{os.path.relpath(path, ROOT)}: no {begin} ... {end} markers", file=sys.stderr)
        return False
    block = (f"{begin}\n<!-- generated by `python3 -m lab.make_docs` from {source} -->\n"
             f"{body.rstrip()}\n{end}")
    new = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: block, text, flags=re.S)
    if new != text:
        with open(path, "w") as f:
            f.write(new)
        print(f"{os.path.relpath(path, ROOT)}: {name} rewritten")
    else:
        print(f"{os.path.relpath(path, ROOT)}: {name} unchanged")
    return True


def work_precision_blocks():
    """The work-precision study's four tables in docs/performance.md."""
    study, table, settled = study_tables.load(os.path.join(RESULTS, "work_precision.json"))
    source = "lab/results/work_precision.json"
    blocks = {
        "work-precision-dt70": study_tables.dt70_table(table),
        "work-precision-peer": study_tables.peer_table(table),
        "work-precision-order": study_tables.order_table(table),
        "work-precision-steel": study_tables.two_readings(table, settled, "steel-stops"),
    }
    ok = all(replace_block(PERFORMANCE, name, "\n".join(lines), source) for name, lines in blocks.items())
    source = "lab/results/work_precision.csv, work_precision.json, profile.json"
    for name, body in work_precision_notes.blocks().items():
        ok = replace_block(PERFORMANCE, name, body, source) and ok
    return ok


def load(name):
    with open(os.path.join(RESULTS, name)) as f:
        return json.load(f)


def in_short_block():
    """The summary at the top of docs/performance.md, from the studies' result files."""
    scenes = load("paper_scenes.json")
    fast = [r["us_fastest"] for r in scenes["scenes"]]
    dt70 = next(r for r in scenes["scenes"] if r["scene"] == "paper-hydraulic-dt70")
    scipy = next(r for r in scenes["scipy_rk45"] if r["rtol"] == 1e-6)
    _, table, _ = study_tables.load(os.path.join(RESULTS, "work_precision.json"))
    at = {m: r.get("1e-06") for m, r in table["paper-hydraulic-dt70"].items()}
    us = lambda m: 1e6 * at[m][0]
    times = lambda m: at["RK45"][0] / at[m][0]
    sweep = load("sweep_bench.json")["threads_2"]
    parts = [c["parts"]["right-hand side"] for c in load("profile.json")["cases"]]
    return "\n".join([
        f"- A paper scene takes {min(fast):.0f}-{max(fast):.0f} µs a run at the defaults (rtol 1e-6); on the "
        f"hydraulic scene SciPy's RK45 takes {1e3 * scipy['ms_per_run'] / dt70['us_fastest']:.0f} times as long "
        "for the same physics.",
        "- At an object final speed error of 1e-6 on the hydraulic paper scene (dead time 70 ms), "
        f"`dop853` takes {us('dop853'):.0f} µs, {times('dop853'):.0f} times less than SciPy RK45; `dp5` "
        f"{us('dp5'):.0f} µs ({times('dp5'):.0f} times), {us('dp5_no_ledger'):.0f} µs with the energy ledger "
        f"off ({times('dp5_no_ledger'):.0f} times). `dp5` takes {at['dp5'][1]:,.0f} evaluations there, "
        f"Hairer's DOPRI5 {at['hairer-dopri5'][1]:,.0f}.",
        "- Against the compiled peer (CyRK with a numba right-hand side): ahead on both hydraulic paper "
        "scenes and on the oscillator at every error level; on the steel stops behind at the levels "
        "the error first crosses, ahead where it stays below them, and ahead at every level over an "
        "ensemble of eight dead times (the work-precision study below).",
        f"- The design-space sweep: {sweep['runs'] / sweep['wall_seconds']:,.0f} runs/s on 2 threads (the "
        "profile-guided build is about an eighth faster).",
        f"- {100 * (1 - max(parts)):.0f}-{100 * (1 - min(parts)):.0f} % of a run's time is spent outside the "
        "right-hand side (events, observers, stepping).",
    ])


def energy_ledger_block():
    """docs/accuracy.md's residuals of the paper scenes and the design space."""
    tail = load("ringing_tail.json")
    design = load("design_accuracy.json")["energy_residual"]
    scenes = ", ".join(f"{r['scene'].removeprefix('paper-')} {sci(r['energy_residual'][0])}" for r in tail["scenes"])
    d = tail["design_space"]
    return "\n".join([
        f"- Paper scenes at rtol 1e-6 (DOPRI5): {scenes}.",
        f"- Design space (`sweeps/design-space.toml`, 16,384 runs at rtol 1e-6): median {sci(design['median'])}, "
        f"largest {sci(design['largest'])}; under DOPRI5 with the ringing tail on and off "
        f"(`solver.ringing_tail = false`), median {sci(d['energy_residual_median'][0])} and "
        f"{sci(d['energy_residual_median'][1])}, largest {sci(d['energy_residual_largest'][0])} and "
        f"{sci(d['energy_residual_largest'][1])} (the ledger over a ringing tail is computed from the force "
        "law, not closed: [model.md](model.md#early-end-and-ringing-tail)).",
    ])


def study_tables_mode(script):
    """Run a study's own `--tables` mode (`python -m lab.NAME --tables`)."""
    venv = os.path.join(ROOT, ".venv", "bin", "python")
    python = venv if os.path.exists(venv) else sys.executable
    cmd = [python, "-m", f"lab.{script[:-3]}", "--tables"]
    done = subprocess.run(cmd, cwd=ROOT)
    if done.returncode != 0:
        print(f"{' '.join(cmd)}: exit status {done.returncode}", file=sys.stderr)
    return done.returncode == 0


STUDIES = {
    "default-method": "default_method.py",
    "design-vs-brute": "design_vs_brute.py",
    "sensitivity-speed": "sensitivity_speed.py",
    "steel-ensemble": "steel_ensemble.py",
    "stability-map": "stability_map.py",
    "run-time-parts": "profile.py",
    "fidelity": "fidelity.py",
    "scene-tolerances": "scene_tolerances.py",
    "ringing-tail": "ringing_tail.py",
    "paper-scenes": "paper_scenes.py",
    "options-cost": "options_cost.py",
    "design-space-sweep": "sweep_bench.py",
    "design-phases": "design_phases.py",
    "python-package": "python_overhead.py",
    "design-accuracy": "design_accuracy.py",
    "options-accuracy": "options_accuracy.py",
    "stiff-ode": "stiff_ode.py",
    "arenstorf": "arenstorf.py",
    "wide-accuracy": "wide_accuracy.py",
    "ringing-tail-check": "ringing_tail_check.py",
    "wide-trajectories": "wide_trajectories.py",
    "stiff-scenes": "stiff_scenes.py",
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skip", nargs="*", default=[], choices=sorted(["in-short", "energy-ledger", "work-precision", *STUDIES]),
                    help="leave these blocks as they are (a study whose results are being made)")
    args = ap.parse_args()
    ok = True
    if "work-precision" not in args.skip:
        ok = work_precision_blocks()
    for name, script in STUDIES.items():
        if name not in args.skip:
            ok = study_tables_mode(script) and ok
    if "energy-ledger" not in args.skip:
        source = "lab/results/ringing_tail.json, design_accuracy.json"
        ok = replace_block(os.path.join(ROOT, "docs", "accuracy.md"), "energy-ledger", energy_ledger_block(),
                           source) and ok
    if "in-short" not in args.skip:
        source = "lab/results/paper_scenes.json, work_precision.json, sweep_bench.json, profile.json"
        ok = replace_block(PERFORMANCE, "in-short", in_short_block(), source) and ok
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
