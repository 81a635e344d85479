"""Figures of runs: the paper's figure 3 for one run, figures 4-6 for two side by side."""

from __future__ import annotations

import os
from typing import Any, Iterable, NamedTuple, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .._cushion import COLUMNS, FIGURE3, FIGURE3_MARKS
from ._units import _save, label


class _Curve(NamedTuple):
    column: str
    label: str
    color: str


class _Panel(NamedTuple):
    title: str
    ylabel: str
    factor: float  # SI -> the panel's unit
    curves: tuple[_Curve, ...]


def _math(symbol: str) -> str:
    """A layout symbol ("x_r", "p_1") as matplotlib math text."""
    return f"${symbol}$" if symbol else ""


def _panel(spec: dict[str, Any]) -> _Panel:
    """A panel of the layout the command's SVG draws too (the extension's ``FIGURE3``)."""
    ylabel = " ".join(x for x in (spec["quantity"], _math(spec["symbol"])) if x) + f" [{spec['unit']}]"
    curves = tuple(_Curve(c["column"], f"{c['name']} {_math(c['symbol'])}", c["color"]) for c in spec["curves"])
    return _Panel(spec["title"], ylabel, spec["factor"], curves)


_POSITIONS_SPEC, _VELOCITIES_SPEC, _GAS_SPEC, _FORCES_SPEC = FIGURE3
_POSITIONS, _VELOCITIES, _GAS, _FORCES = (_panel(spec) for spec in FIGURE3)
_F_R = next(c for c in _FORCES.curves if c.column == "F_r")
# The comparison's second row: the force on the robot alone, in the forces panel's unit and colour.
_ROBOT_FORCE = _Panel(
    "Force on the robot", f"force on the robot $F_r$ [{_FORCES_SPEC['unit']}]", _FORCES.factor,
    (_F_R._replace(label="$F_r$"),),
)
# The dashed event lines: (label, summary field, colour).
_MARKS = tuple((m["label"], m["field"], m["color"]) for m in FIGURE3_MARKS)
# The event whose first time a mark's summary field reports (for a run recorded without a summary).
_EVENT_OF_FIELD = {"t_detect": "sensor", "t_brake": "brake"}


def _first_event(run: Any, name: str) -> float | None:
    events = run.events
    hits = events.loc[events["event"] == name, "t"]
    return float(hits.iloc[0]) if len(hits) else None


def marks(run: Any) -> dict[str, float | None]:
    """Detection and brake times of a run in s (``None`` when they never happen): from its
    summary (``t_detect``, ``t_brake``), or, for a recorded run without one, from its first
    ``sensor`` and ``brake`` events."""
    s = run.summary
    if s is not None:
        return {label: s.get(field) for label, field, _ in _MARKS}
    return {label: _first_event(run, _EVENT_OF_FIELD[field]) for label, field, _ in _MARKS}


def _window(run: Any, t_max: float | None) -> dict[str, np.ndarray]:
    """The run's trajectory columns up to ``t_max`` (s) and the first point after it, so the
    curves reach the axis's end and the y-limits fit what is shown."""
    t = run.t
    n = len(t) if t_max is None else min(int(np.searchsorted(t, t_max, side="right")) + 1, len(t))
    return {c: getattr(run, c)[:n] for c in COLUMNS}


def _has_values(data: dict[str, np.ndarray], panel: _Panel) -> bool:
    return any(np.isfinite(data[c.column]).any() for c in panel.curves)


def _draw_panel(ax: Axes, data: dict[str, np.ndarray], panel: _Panel, *, legend: bool = True) -> None:
    t_ms = data["t"] * 1e3
    for k, c in enumerate(panel.curves):
        y = data[c.column] * panel.factor
        if not np.isfinite(y).any():
            continue  # the scene lacks it (no object): no empty legend entry
        # The first curve is drawn wider, so one lying on it (rigid: tool on flange) shows both.
        width = 2.6 if k == 0 and len(panel.curves) > 1 else 1.5
        ax.plot(t_ms, y, color=c.color, lw=width, label=c.label)
    ax.set_ylabel(panel.ylabel)
    ax.set_title(panel.title, loc="left", fontsize="medium")
    ax.grid(True, color="0.9")
    if legend:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)


def _draw_marks(
    ax: Axes, times: dict[str, float | None], *, with_time: bool = True, in_legend: bool = True
) -> None:
    """Dashed vertical lines at detection (red) and brake start (grey), x in ms; each line's
    gid is ``"detection"`` or ``"brake start"`` so it can be found again."""
    for name, _, color in _MARKS:
        t = times.get(name)
        if t is None or not np.isfinite(t):
            continue
        text = f"{name} {t * 1e3:.1f} ms" if with_time else name
        if not in_legend:
            text = "_" + text  # matplotlib leaves labels starting with "_" out of legends
        line = ax.axvline(t * 1e3, color=color, ls="--", lw=1.3, label=text)
        line.set_gid(name)


def _short_summary(run: Any) -> str:
    s = run.summary
    if s is None:
        return "recorded run"
    parts = [f"peak $|F_r|$ {abs(s['peak_robot_force']):.1f} N"]
    v = s.get("object_final_velocity")
    if v is not None and np.isfinite(v):
        parts.append(f"object final speed {v:.2f} m/s")
    if s.get("status") not in (None, "ok"):
        parts.append(f"status {s['status']}")
    return ", ".join(parts)


def _time_limits(runs: Iterable[Any], t_max: float | None) -> tuple[float, float]:
    t0 = min(float(r.t[0]) for r in runs) * 1e3
    t1 = (t_max * 1e3) if t_max is not None else max(float(r.t[-1]) for r in runs) * 1e3
    return t0, t1


def _check_trajectory(run: Any) -> None:
    if len(run.t) == 0:
        raise ValueError("this run has no trajectory: simulate it with trajectory=True")


def run(
    run: Any,
    *,
    path: str | os.PathLike[str] | None = None,
    title: str | None = None,
    fig: Figure | None = None,
    t_max: float | None = None,
) -> Figure:
    """The paper's figure 3 for one run, over time in ms:

    1. positions of robot flange ``x_r``, tool ``x_t`` and object ``x_p`` (mm),
    2. their velocities ``v_r, v_t, v_p`` (m/s),
    3. gas pressure ``p1`` (kPa; left out, and said so in the title, when the scene has no gas:
       bistable or rigid module),
    4. force on the robot ``F_r`` and tool-object contact force ``F_c`` (N).

    Detection (red) and brake start (grey) are dashed vertical lines in every panel, at the
    summary's ``t_detect`` and ``t_brake``, or at the ``sensor`` and ``brake`` events of a
    recorded run (``summary`` None).

    Parameters
    ----------
    run
        A :class:`cushion.Run` with its trajectory.
    path
        Write the figure there (PNG, SVG, PDF by extension).
    title
        The figure's title (default: peak robot force and object final speed).
    fig
        Draw into this figure (cleared first) instead of a new one.
    t_max
        End of the time axis in s (default: the whole run).
    """
    _check_trajectory(run)
    panels = [_POSITIONS, _VELOCITIES, _GAS, _FORCES]
    data = _window(run, t_max)
    has_gas = _has_values(data, _GAS)
    if not has_gas:
        panels.remove(_GAS)
    if fig is None:
        fig = plt.figure(figsize=(10, 2.6 * len(panels) + 0.8), layout="constrained")
    else:
        fig.clear()
    axes = fig.subplots(len(panels), 1, sharex=True)
    times = marks(run)
    for k, (ax, panel) in enumerate(zip(axes, panels)):
        _draw_panel(ax, data, panel, legend=False)
        _draw_marks(ax, times, in_legend=k == 0)  # their legend once, on the top panel
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    axes[-1].set_xlabel("time [ms]")
    axes[-1].set_xlim(*_time_limits([run], t_max))
    heading = title if title is not None else _short_summary(run)
    if not has_gas:
        heading += "\n(no gas in this scene: no pressure panel)"
    fig.suptitle(heading)
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# Two runs side by side: the paper's figures 4-6
# --------------------------------------------------------------------------------------------


def compare(
    a: Any,
    b: Any,
    *,
    labels: Sequence[str] = ("hydraulic", "bistable"),
    path: str | os.PathLike[str] | None = None,
    title: str | None = None,
    t_max: float | None = None,
) -> Figure:
    """Two runs side by side (one column each), as the paper's figures 4-6 compare the
    hydraulic and the bistable module: top row velocities ``v_r, v_t, v_p`` (m/s), bottom row
    force on the robot ``F_r`` (N), time in ms. Each row shares its y-limits, so the columns
    compare at a glance. Detection (red) and brake start (grey) are dashed vertical lines;
    each column's heading gives their times, the peak ``|F_r|`` and the object's final speed.

    Parameters
    ----------
    a, b
        :class:`cushion.Run` objects with trajectories (left and right column).
    labels
        Column headings (e.g. the modules).
    path
        Write the figure there.
    title
        The figure's title.
    t_max
        End of the shared time axis in s (default: the longer run).
    """
    for r in (a, b):
        _check_trajectory(r)
    fig, axes = plt.subplots(2, 2, figsize=(13, 7.5), sharex=True, sharey="row", layout="constrained")
    for col, (r, name) in enumerate(zip((a, b), labels)):
        times = marks(r)
        data = _window(r, t_max)
        for row, panel in enumerate((_VELOCITIES, _ROBOT_FORCE)):
            ax = axes[row, col]
            _draw_panel(ax, data, panel, legend=False)
            _draw_marks(ax, times, with_time=False)
            ax.set_title("", loc="left")  # the row is named by its y label
            if col == 1:
                ax.set_ylabel("")
                ax.tick_params(labelleft=True)  # shared limits, but keep the numbers readable
        heading = [f"{name}: {_short_summary(r)}"]
        when = [f"{k} {t * 1e3:.1f} ms" for k, t in times.items() if t is not None]
        if when:
            heading.append(", ".join(when))
        axes[0, col].set_title("\n".join(heading), fontsize="medium")
        axes[1, col].set_xlabel("time [ms]")
    for row in range(2):
        axes[row, 1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    axes[0, 0].set_xlim(*_time_limits([a, b], t_max))
    if title is not None:
        fig.suptitle(title)
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# Sweeps
# --------------------------------------------------------------------------------------------

#: Up to this many distinct values, an axis is grouped by its values; beyond, by bins.
