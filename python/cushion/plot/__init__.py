"""Figures of one run and of sweeps, drawn with matplotlib (``pip install cushion[plot]``).

>>> import cushion, cushion.plot
>>> run = cushion.simulate()                       # the paper's hydraulic scene, dead time 70 ms
>>> cushion.plot.run(run, path="fig3.png")        # the paper's figure 3
>>> a = cushion.simulate("sweeps/scenes/paper-hydraulic-dt10.toml")
>>> b = cushion.simulate("sweeps/scenes/paper-bistable-dt10.toml")
>>> cushion.plot.compare(a, b, path="fig5-6.png")   # the paper's figures 5 and 6
>>> frame = cushion.sweep("sweeps/design-space.toml")
>>> cushion.plot.metric_vs_axis(frame, "object_final_velocity", "robot.dead_time", by="module")
>>> cushion.plot.heatmap(frame, "peak_robot_force", "hydraulic.gas_pressure",
...                      "hydraulic.orifice_radius")
>>> answer = cushion.design("sweeps/design-question.toml")
>>> cushion.plot.design_map(answer, path="design-map.png")   # the feasible region
>>> frame = cushion.sensitivity("sweeps/sensitivity.toml")
>>> cushion.plot.sensitivity(frame, path="sensitivity.png")   # S1, ST, S2

Every function returns the :class:`matplotlib.figure.Figure` it drew on and writes it to
``path`` when given (the format follows the file's extension: ``.png``, ``.svg``, ``.pdf``).
Nothing here calls ``plt.show()``. Inputs are SI (s, m, m/s, Pa, N, kg); the figures show
some quantities in handier units (time in ms, positions and radii in mm, gas pressure of a
run in kPa), and every axis label names its unit.

The panels mirror the SVG figures of the ``cushion`` command (``simulate --plot`` and the sweep
report), so a figure made here reads like one made there.

Backend: a backend chosen by you (``matplotlib.use``, ``MPLBACKEND``, a ``matplotlibrc``) or by
Jupyter stands. When none is chosen, importing this module selects the off-screen ``Agg``
backend, so scripts and servers never open windows; to see windows from a plain script, pick a
GUI backend (``matplotlib.use("QtAgg")``) before importing ``cushion.plot``.
"""


from __future__ import annotations

import matplotlib


def _choose_backend() -> None:
    # rcParams holds a sentinel until a backend is named or resolved; we choose only while it
    # does, so a notebook's inline backend or a user's GUI backend is never overridden.
    get = getattr(matplotlib.rcParams, "_get_backend_or_none", None)
    if get is not None and get() is None:
        matplotlib.use("Agg")


_choose_backend()


_choose_backend()

from ._runs import compare, marks, run  # noqa: E402  (after the backend is settled)
from ._design import design_map  # noqa: E402
from ._sensitivity import sensitivity  # noqa: E402
from ._sweeps import heatmap, metric_vs_axis  # noqa: E402
from ._units import AXES, METRICS, MODULE_COLORS, Quantity, label, quantity  # noqa: E402

__all__ = [
    "METRICS",
    "AXES",
    "MODULE_COLORS",
    "Quantity",
    "quantity",
    "label",
    "marks",
    "run",
    "compare",
    "metric_vs_axis",
    "heatmap",
    "design_map",
    "sensitivity",
]
