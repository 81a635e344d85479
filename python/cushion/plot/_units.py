"""Names, units and display scales of the quantities the figures show, and the helpers every
figure shares."""

from __future__ import annotations

import functools
import os
from typing import NamedTuple

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .._cushion import QUANTITIES

# Names, units and display scales
# --------------------------------------------------------------------------------------------


class Quantity(NamedTuple):
    """How a column is shown: a readable ``name``, the ``unit`` on the axis, and the ``factor``
    that turns the SI value into that unit (``robot.dead_time`` in s -> ms: 1e3)."""

    name: str
    unit: str
    factor: float = 1.0


#: Summary metrics (the columns of a sweep's frame, the keys of ``Run.summary``), as shown; the
#: table the command's sweep report reads too (the extension's ``QUANTITIES``).
METRICS: dict[str, Quantity] = {
    q["key"]: Quantity(q["name"], q["unit"], q["factor"]) for q in QUANTITIES if q["kind"] == "metric"
}

#: Scene keys shown in other words or units than ``cushion.keys()`` gives; every other key is
#: shown by its name in its SI unit from ``cushion.keys()``.
AXES: dict[str, Quantity] = {
    q["key"]: Quantity(q["name"], q["unit"], q["factor"]) for q in QUANTITIES if q["kind"] == "axis"
}


@functools.lru_cache(maxsize=1)
def _key_units() -> dict[str, str]:
    from .. import keys

    frame = keys()
    return dict(zip(frame["key"], frame["unit"]))


def quantity(name: str) -> Quantity:
    """How the column ``name`` (a summary metric or a scene key) is shown: readable name, unit,
    factor from SI. Unknown names are shown as they are, unit unknown (empty)."""
    if name in METRICS:
        return METRICS[name]
    if name in AXES:
        return AXES[name]
    unit = _key_units().get(name)
    if unit is not None:
        return Quantity(name, unit if unit else "-")
    return Quantity(name, "")


def label(name: str, magnitude: bool = False) -> str:
    """An axis label with its unit: ``"peak robot force [N]"``, or with ``magnitude``
    ``"|peak robot force| [N]"``."""
    q = quantity(name)
    text = f"|{q.name}|" if magnitude else q.name
    return f"{text} [{q.unit}]" if q.unit else text


# --------------------------------------------------------------------------------------------
# Common helpers
# --------------------------------------------------------------------------------------------

#: Colours per module, as in the command's sweep report.
MODULE_COLORS = {"hydraulic": "#1f77b4", "bistable": "#ff7f0e", "rigid": "#6e6e6e"}



def _save(fig: Figure, path: str | os.PathLike[str] | None) -> Figure:
    if path is not None:
        # 130 dpi: sharp enough on a screen, small enough to commit.
        fig.savefig(os.fspath(path), dpi=130)
    return fig


def _new_axes(ax: Axes | None, figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig, ax = plt.subplots(figsize=figsize, layout="constrained")
    return fig, ax


def _ok_rows(frame: pd.DataFrame) -> tuple[pd.DataFrame, int]:
    """Rows whose run ended ``ok`` (a failed run's metrics are not results), and how many were
    left out."""
    if "status" not in frame.columns:
        return frame, 0
    ok = frame[frame["status"] == "ok"]
    return ok, len(frame) - len(ok)


def _runs_note(n_ok: int, left_out: int) -> str:
    note = f"{n_ok} runs"
    return note + (f", {left_out} failed runs left out" if left_out else "")


def _is_log(values: np.ndarray) -> bool:
    """Whether an axis is best shown on a log scale: positive, spanning over 2 decades, and
    spread evenly in log rather than linearly. The last test is that the middle 80 % of the
    values span over 1.5 decades: a dead time drawn evenly from 0 to 100 ms also has a
    smallest value 3 decades below its largest, but its middle 80 % span less than one."""
    v = values[np.isfinite(values)]
    if v.size == 0 or v.min() <= 0 or v.max() / v.min() <= 100.0:
        return False
    q10, q90 = np.quantile(v, [0.1, 0.9])
    return q90 / q10 > 10**1.5


# --------------------------------------------------------------------------------------------
# One run: the paper's figure 3
# --------------------------------------------------------------------------------------------


