"""What the ringing tail earns: each paper scene, and the design space, with the ringing tail on
and off (`solver.ringing_tail`), under DOPRI5 at rtol 1e-6.

    python3 -m lab.ringing_tail            # about a minute after the release build
    python3 -m lab.ringing_tail --tables   # docs/performance.md's block from the results

Per paper scene (`cushion simulate SCENE --json`): steps and evaluations with the tail and
without it, how far the robot impulse moves (relative), the energy ledger's residual both ways;
the same steps under Rodas4. On the design space (`sweeps/design-space.toml` with
`solver.method = "dp5"`, and again with the tail off): the steps and evaluations in all, the wall
time of the whole command (3 interleaved rounds each, 2 threads), and how far the summaries
move: object final speeds and largest strokes, peak robot forces (relative), robot impulses.

Writes lab/results/ringing_tail.json; the block `ringing-tail` of docs/performance.md is drawn
from it (here and by `python3 -m lab.make_docs`).
"""

import os
import subprocess
import tempfile
import time

from lab import study as lab
from lab.make_docs import PERFORMANCE
from lab.study import sci

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = lab.binary("cushion")
RESULTS = os.path.join(ROOT, "lab", "results", "ringing_tail.json")
SCENES = ["paper-hydraulic-dt70", "paper-hydraulic-dt10", "paper-bistable-dt70", "paper-bistable-dt10",
          "paper-rigid"]
OFF = "solver.ringing_tail=false"
ROUNDS = 3


def simulate(scene, sets):
    return lab.simulate(os.path.join(ROOT, "sweeps", "scenes", f"{scene}.toml"), sets)


def scene_row(scene):
    on, off = simulate(scene, ["solver.method=dp5"]), simulate(scene, ["solver.method=dp5", OFF])
    r_on, r_off = simulate(scene, ["solver.method=rodas"]), simulate(scene, ["solver.method=rodas", OFF])
    return {
        "scene": scene,
        "steps": [on["stats"]["steps"], off["stats"]["steps"]],
        "rhs_evals": [on["stats"]["rhs_evals"], off["stats"]["rhs_evals"]],
        "robot_impulse_rel": abs(on["robot_impulse"] - off["robot_impulse"]) / abs(off["robot_impulse"]),
        "energy_residual": [on["energy_residual"], off["energy_residual"]],
        "rodas_steps": [r_on["stats"]["steps"], r_off["stats"]["steps"]],
    }


def sweep_file(tmp, tail):
    """sweeps/design-space.toml under DOPRI5, with the tail on or off."""
    sets = {"solver.method": '"dp5"', **({} if tail else {"solver.ringing_tail": "false"})}
    return lab.design_space_file(tmp, f"design-space-{'on' if tail else 'off'}", sets)


def design_space():
    import pandas as pd

    with tempfile.TemporaryDirectory() as tmp:
        files = {tail: sweep_file(tmp, tail) for tail in (True, False)}
        walls = {True: [], False: []}
        for _ in range(ROUNDS):
            for tail in (True, False):
                out = os.path.join(tmp, f"out-{tail}")
                start = time.perf_counter()
                subprocess.run([CLI, "sweep", files[tail], "--out", out, "--threads", "2", "--quiet"], check=True)
                walls[tail].append(time.perf_counter() - start)
        on = pd.read_parquet(os.path.join(tmp, "out-True", "summary.parquet"))
        off = pd.read_parquet(os.path.join(tmp, "out-False", "summary.parquet"))
    impulse = (on["robot_impulse"] - off["robot_impulse"]).abs()
    return {
        "runs": len(on),
        "not_ok": int((on["status"] != "ok").sum() + (off["status"] != "ok").sum()),
        "steps": [int(on["stats_steps"].sum()), int(off["stats_steps"].sum())],
        "rhs_evals": [int(on["stats_rhs_evals"].sum()), int(off["stats_rhs_evals"].sum())],
        "wall_seconds": [sorted(walls[True]), sorted(walls[False])],
        "object_final_velocity_max_diff": float((on["object_final_velocity"] - off["object_final_velocity"]).abs().max()),
        "max_stroke_max_diff": float((on["max_stroke"] - off["max_stroke"]).abs().max()),
        "peak_robot_force_max_rel": float(((on["peak_robot_force"] - off["peak_robot_force"]).abs()
                                           / off["peak_robot_force"].abs()).max()),
        "robot_impulse_max_diff": float(impulse.max()),
        "robot_impulse_median_diff": float(impulse.median()),
        "energy_residual_median": [float(on["energy_residual"].median()), float(off["energy_residual"].median())],
        "energy_residual_largest": [float(on["energy_residual"].max()), float(off["energy_residual"].max())],
    }


def table(study):
    out = ["| method | scene | steps on / off | rhs evaluations on / off | robot impulse moves by (rel) | "
           "energy residual on / off |", "|---|---|---|---|---|---|"]
    for r in study["scenes"]:
        moved = "0 (no ringing)" if r["robot_impulse_rel"] == 0 and r["steps"][0] == r["steps"][1] else (
            sci(r["robot_impulse_rel"]))
        out.append(f"| dp5 | {r['scene']} | {r['steps'][0]:,} / {r['steps'][1]:,} | {r['rhs_evals'][0]:,} / "
                   f"{r['rhs_evals'][1]:,} | {moved} | {sci(r['energy_residual'][0])} / {sci(r['energy_residual'][1])} |")
    ringing = [r for r in study["scenes"] if r["steps"][0] != r["steps"][1]]
    ratios = [r["rodas_steps"][1] / r["rodas_steps"][0] for r in ringing]
    d = study["design_space"]
    same = lambda x: "identical to the bit" if x == 0 else f"within {sci(x)}"
    w_on, w_off = d["wall_seconds"]
    out += ["", f"On the design space ({d['runs']:,} runs, dp5; `\"solver.ringing_tail\" = false` in the sweep "
            f"file's `[set]`; {d['not_ok']} runs not ok): {d['steps'][0] / 1e6:.2f} M / {d['steps'][1] / 1e6:.2f} M "
            f"steps, {d['rhs_evals'][0] / 1e6:.1f} M / {d['rhs_evals'][1] / 1e6:.1f} M evaluations, "
            f"{w_on[0]:.2f}-{w_on[-1]:.2f} s / {w_off[0]:.2f}-{w_off[-1]:.2f} s on 2 threads (the whole command); "
            f"object final speeds {same(d['object_final_velocity_max_diff'])}, largest strokes "
            f"{same(d['max_stroke_max_diff'])}, peak robot forces within {sci(d['peak_robot_force_max_rel'])} "
            f"(relative), robot impulses within {sci(d['robot_impulse_max_diff'])} N s (median "
            f"{sci(d['robot_impulse_median_diff'])}). Under Rodas4 the paper scenes with ringing take "
            f"{min(ratios):.1f}-{max(ratios):.1f} times fewer steps with the tail."]
    return out


def measure(args=None):
    lab.release("cushion")
    return {"scenes": [scene_row(s) for s in SCENES], "design_space": design_space()}


def blocks(study):
    return [(PERFORMANCE, "ringing-tail", "\n".join(table(study)))]


def main():
    lab.main(__doc__, RESULTS, measure, blocks)


if __name__ == "__main__":
    main()
