"""Redraw the paper's figures from cushion's runs, as PNG files.

    python examples/paper_figures.py [OUTDIR]        # default: docs/figures of this repository

The copy of the paper this project works from ("Development of a hydraulic system for the
mitigation of end-effector collisions") is text only, its figures lost; its text says what
each one showed. The files written here, and the paper figure each stands for:

fig3-hydraulic-dt70.png
    Paper Fig. 3: the hydraulic module, dead time DT = 70 ms: (a) positions and (b) velocities
    of robot flange, tool and object, (c) gas pressure, (d) force on the robot F_r (here with
    the tool-object contact force F_c beside it). Detection and brake start are marked.
fig4-compare-dt70.png
    Paper Fig. 4: the bistable module at DT = 70 ms, (a) velocities and (b) force on the robot,
    in the right column; the left column is the hydraulic module at the same dead time, which
    the paper's text compares it with (its Fig. 3b and 3d), on the same scales.
fig5-6-compare-dt10.png
    Paper Figs. 5 and 6: DT = 10 ms, hydraulic (a, left) against bistable (b, right); the top
    row is Fig. 5 (velocities), the bottom row Fig. 6 (forces on the robot).
rigid-vs-hydraulic-dt70.png
    Not in the paper: the baseline without mitigation (tool bolted to the flange) beside the
    hydraulic module, DT = 70 ms.
sweep-dead-time.png
    Not in the paper: object final speed and peak robot force against dead time, 0 to 100 ms in
    steps of 5 ms, for the three modules (3 x 21 runs): where the paper's two findings (the
    hydraulic module leaves the object slower at 70 ms, the bistable one at 10 ms) cross over.

Time axes end at 200 ms: the robot has stopped by 175 ms and nothing changes afterwards. The
whole script takes a few seconds (the 67 runs take well under one).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import matplotlib.pyplot as plt

import cushion
import cushion.plot

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "sweeps" / "scenes"

#: End of the time axes in s: the robot stands still from 175 ms on (brake at ~75 ms + 100 ms).
T_MAX = 0.2


def simulate(name: str) -> cushion.Run:
    """One of the paper's scenes (``sweeps/scenes/paper-<name>.toml``), sampled every 0.1 ms
    so the curves are smooth."""
    return cushion.simulate(SCENES / f"paper-{name}.toml", sample_interval=1e-4)


def dead_time_sweep() -> "pandas.DataFrame":  # noqa: F821 (pandas only named here)
    """The three modules at dead times 0, 5, ..., 100 ms in the paper's scene (3 x 21 runs)."""
    return cushion.sweep(
        {
            "name": "dead-time",
            "scene": str(SCENES / "paper-hydraulic-dt70.toml"),
            "sampling": {"mode": "grid"},
            "axis": [
                {"key": "module", "values": ["hydraulic", "bistable", "rigid"]},
                {"key": "robot.dead_time", "linspace": [0.0, 0.1, 21]},
            ],
        },
        progress=False,
    )


def sweep_figure(frame, path: Path) -> None:
    """Object final speed (m/s) and |peak robot force| (N) against dead time (ms), by module."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.8), layout="constrained")
    cushion.plot.metric_vs_axis(frame, "object_final_velocity", "robot.dead_time", by="module", ax=left)
    cushion.plot.metric_vs_axis(
        frame, "peak_robot_force", "robot.dead_time", by="module", ax=right, magnitude=True
    )
    left.set_title("Object final speed")
    right.set_title("Peak force on the robot")
    fig.suptitle(f"The paper's scene against dead time ({len(frame)} runs, one per point)")
    fig.savefig(path, dpi=130)


def main(outdir: Path) -> list[Path]:
    """Write every figure into ``outdir``; returns the files written."""
    outdir.mkdir(parents=True, exist_ok=True)
    runs = {name: simulate(name) for name in ("hydraulic-dt70", "hydraulic-dt10", "bistable-dt70", "bistable-dt10", "rigid")}
    for name, r in runs.items():
        s = r.summary
        print(f"{name:15s} peak F_r {s['peak_robot_force']:8.2f} N   object speed {s['object_final_velocity']:.3f} m/s")

    written: list[Path] = []

    def out(name: str) -> Path:
        written.append(outdir / name)
        return outdir / name

    cushion.plot.run(
        runs["hydraulic-dt70"],
        path=out("fig3-hydraulic-dt70.png"),
        title="Hydraulic module, dead time 70 ms (paper Fig. 3)",
        t_max=T_MAX,
    )
    cushion.plot.compare(
        runs["hydraulic-dt70"],
        runs["bistable-dt70"],
        path=out("fig4-compare-dt70.png"),
        title="Dead time 70 ms: hydraulic against bistable (paper Fig. 4, with Fig. 3b and 3d)",
        t_max=T_MAX,
    )
    cushion.plot.compare(
        runs["hydraulic-dt10"],
        runs["bistable-dt10"],
        path=out("fig5-6-compare-dt10.png"),
        title="Dead time 10 ms: hydraulic against bistable (paper Fig. 5: velocities, Fig. 6: forces)",
        t_max=T_MAX,
    )
    cushion.plot.compare(
        runs["rigid"],
        runs["hydraulic-dt70"],
        labels=("rigid (no module)", "hydraulic"),
        path=out("rigid-vs-hydraulic-dt70.png"),
        title="Dead time 70 ms: no mitigation (tool bolted to the flange) against the hydraulic module",
        t_max=T_MAX,
    )
    sweep_figure(dead_time_sweep(), out("sweep-dead-time.png"))
    plt.close("all")  # a script: free the figures once written
    return written


if __name__ == "__main__":
    start = time.perf_counter()
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs" / "figures"
    for path in main(target):
        print("wrote", path)
    print(f"{time.perf_counter() - start:.1f} s")
