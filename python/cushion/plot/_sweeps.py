"""Views of a sweep: a metric against one axis grouped by another, and a heat map of a
metric's worst case over two axes."""

from __future__ import annotations

import os
from typing import Any, NamedTuple, Sequence

import matplotlib
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ._units import label, MODULE_COLORS, quantity, _is_log, _new_axes, _ok_rows, _runs_note, _save


EXACT_GROUPS = 25


def _groups_by_quantile(x: pd.Series, bins: int = 12) -> pd.Series:
    """Group labels for an axis: its values when few (<= 25), else ~``bins`` quantile bins
    (equal run counts, so each median rests on as many runs)."""
    if x.nunique() <= EXACT_GROUPS:
        return x
    return pd.qcut(x, bins, labels=False, duplicates="drop")


class _Groups(NamedTuple):
    labels: pd.Series  # one readable group name per row
    names: list[str]  # in drawing order
    colors: dict[str, Any]


def _by_groups(frame: pd.DataFrame, by: str | None) -> _Groups:
    """The grouping column as readable names in drawing order, with colours: modules in the
    paper's order and the report's colours; a numeric column with many values cut into 4
    quantile classes (``"0.05-0.29 kg"``, light to heavy on a sequential colour map)."""
    if by is None:
        labels = pd.Series("all runs", index=frame.index)
        return _Groups(labels, ["all runs"], {"all runs": MODULE_COLORS["hydraulic"]})
    col = frame[by]
    numeric = pd.api.types.is_numeric_dtype(col) and not pd.api.types.is_bool_dtype(col)
    if numeric and col.nunique() > 8:
        q = quantity(by)
        unit = f" {q.unit}" if q.unit and q.unit != "-" else ""
        classes = pd.qcut(col, 4, labels=False, duplicates="drop")
        # Name each class by the values it holds (qcut's own edges are padded by 0.1 %).
        span = col.groupby(classes).agg(["min", "max"]) * q.factor
        name = {k: f"{r['min']:.3g}-{r['max']:.3g}{unit}" for k, r in span.iterrows()}
        names = [name[k] for k in span.index]
        cmap = matplotlib.colormaps["viridis"]
        colors = {n: cmap(0.9 * k / max(len(names) - 1, 1)) for k, n in enumerate(names)}
        return _Groups(classes.map(name), names, colors)
    labels = col.astype(str)
    order = {m: k for k, m in enumerate(MODULE_COLORS)}
    values = list(col.dropna().unique())
    if numeric:
        values.sort()
    else:
        values.sort(key=lambda v: (order.get(str(v), len(order)), str(v)))
    names = [str(v) for v in values]
    colors = {n: MODULE_COLORS.get(n, f"C{(k + 2) % 10}") for k, n in enumerate(names)}
    return _Groups(labels, names, colors)


def _values(frame: pd.DataFrame, metric: str, magnitude: bool) -> pd.Series:
    v = frame[metric].astype(float)
    return v.abs() if magnitude else v


def metric_vs_axis(
    frame: pd.DataFrame,
    metric: str,
    axis: str,
    *,
    by: str | None = None,
    path: str | os.PathLike[str] | None = None,
    ax: Axes | None = None,
    magnitude: bool = False,
) -> Figure:
    """A sweep's metric against one axis, one line per group of ``by``: the median per bin of
    the axis, with the quartiles (25 to 75 %) as a band.

    Bins are the axis's values when it has at most 25 of them (a grid), else about 12
    quantile bins (random samples), each drawn at the median axis value of its runs. Only runs
    with ``status == "ok"`` count; the title says how many were left out. The x axis is
    logarithmic when the axis is positive and spans more than two decades.

    Parameters
    ----------
    frame
        A sweep's rows (:func:`cushion.sweep`).
    metric
        A summary column, e.g. ``"object_final_velocity"`` (m/s) or ``"peak_robot_force"`` (N).
    axis
        An axis column, e.g. ``"robot.dead_time"`` (s, shown in ms).
    by
        A column to group by, e.g. ``"module"``; a numeric column with many values is cut into
        four quantile classes. ``None``: one line.
    path
        Write the figure there.
    ax
        Draw into these axes instead of a new figure.
    magnitude
        Plot ``|metric|`` (the size of a signed peak force, say).
    """
    ok, left_out = _ok_rows(frame)
    qx, qy = quantity(axis), quantity(metric)
    fig, ax = _new_axes(ax, (7.5, 4.6))
    groups = _by_groups(ok, by)
    data = pd.DataFrame(
        {"x": ok[axis].astype(float), "y": _values(ok, metric, magnitude), "group": groups.labels}
    ).dropna()
    data["bin"] = _groups_by_quantile(data["x"])
    for name in groups.names:
        rows = data[data["group"] == name]
        if rows.empty:
            continue
        stats = rows.groupby("bin").agg(
            x=("x", "median"),
            median=("y", "median"),
            q1=("y", lambda v: v.quantile(0.25)),
            q3=("y", lambda v: v.quantile(0.75)),
        )
        stats = stats.sort_values("x")
        color = groups.colors[name]
        x = stats["x"] * qx.factor
        ax.fill_between(x, stats["q1"] * qy.factor, stats["q3"] * qy.factor, color=color, alpha=0.22, lw=0)
        line = ax.plot(x, stats["median"] * qy.factor, "o-", color=color, ms=3.5, lw=1.8, label=name)[0]
        line.set_gid(f"median {name}")
    if _is_log(data["x"].to_numpy()):
        ax.set_xscale("log")
    ax.set_xlabel(label(axis))
    ax.set_ylabel(label(metric, magnitude))
    ax.grid(True, color="0.9")
    if by is not None:
        ax.legend(title=quantity(by).name, fontsize="small")
    shown = f"|{qy.name}|" if magnitude else qy.name
    ax.set_title(f"{shown}: median, band 25-75 % ({_runs_note(len(ok), left_out)})", fontsize="medium")
    return _save(fig, path)


_REDUCERS = {
    "worst": ("max |{}|", lambda v: v.abs().max()),
    "max": ("max {}", lambda v: v.max()),
    "min": ("min {}", lambda v: v.min()),
    "median": ("median {}", lambda v: v.median()),
}


class _Cells(NamedTuple):
    codes: np.ndarray  # cell index per row
    centres: np.ndarray  # SI
    edges: np.ndarray  # SI, len(centres) + 1
    log: bool


def _cells(values: pd.Series, bins: int) -> _Cells:
    """Cells along one axis: its distinct values when at most 25 (edges halfway between, in
    log on a log axis), else ``bins`` equal-width bins (log-spaced on a log axis)."""
    v = values.to_numpy(dtype=float)
    log = _is_log(v)
    to = np.log10 if log else (lambda a: np.asarray(a, dtype=float))
    back = (lambda a: 10.0**a) if log else (lambda a: a)
    distinct = np.unique(v[np.isfinite(v)])
    if distinct.size <= EXACT_GROUPS:
        t = to(distinct)
        if t.size == 1:
            half = 0.5 if log else (0.1 * abs(t[0]) or 0.5)  # one value: a cell around it
            inner = np.array([t[0] - half, t[0] + half])
        else:
            mid = (t[1:] + t[:-1]) / 2
            inner = np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])
        codes = np.searchsorted(distinct, v)
        return _Cells(codes, distinct, back(inner), log)
    lo, hi = to(distinct[0]), to(distinct[-1])
    edges_t = np.linspace(lo, hi, bins + 1)
    codes = np.clip(np.searchsorted(edges_t, to(v), side="right") - 1, 0, bins - 1)
    centres = back((edges_t[1:] + edges_t[:-1]) / 2)
    return _Cells(codes, centres, back(edges_t), log)


def _text_color(rgba: Sequence[float]) -> str:
    r, g, b = rgba[:3]
    return "black" if 0.299 * r + 0.587 * g + 0.114 * b > 0.5 else "white"


def heatmap(
    frame: pd.DataFrame,
    metric: str,
    x: str,
    y: str,
    *,
    reduce: str = "worst",
    path: str | os.PathLike[str] | None = None,
    ax: Axes | None = None,
    bins: int = 12,
) -> Figure:
    """A metric over cells of two axes, reduced over everything else that varies in each cell
    (dead time, object mass, ...): by default its worst case, the largest ``|metric|``.

    Cells are an axis's values when it has at most 25 (a grid), else ``bins`` equal-width bins
    (log-spaced when the axis is positive and spans more than two decades, which is then drawn
    on a log scale). Only runs with ``status == "ok"`` count. Empty cells are left blank; when
    there are at most 100 cells each shows its value.

    Parameters
    ----------
    frame
        A sweep's rows (:func:`cushion.sweep`).
    metric
        A summary column, e.g. ``"peak_robot_force"`` (N).
    x, y
        Axis columns, e.g. ``"hydraulic.gas_pressure"`` (Pa) and ``"hydraulic.orifice_radius"``
        (m, shown in mm).
    reduce
        ``"worst"`` (max of ``|metric|``), ``"max"``, ``"min"`` or ``"median"``.
    path
        Write the figure there.
    ax
        Draw into these axes (a colour bar is added beside them) instead of a new figure.
    bins
        Bins per axis when an axis has more than 25 distinct values.

    The drawn values (in the colour bar's unit) are ``ax.collections[0].get_array()``, shape
    (cells along y, cells along x), masked where a cell holds no run.
    """
    if reduce not in _REDUCERS:
        raise ValueError(f"reduce = {reduce!r}: expected one of {', '.join(_REDUCERS)}")
    ok, left_out = _ok_rows(frame)
    ok = ok[np.isfinite(ok[metric].astype(float))]
    qx, qy, qm = quantity(x), quantity(y), quantity(metric)
    cx, cy = _cells(ok[x], bins), _cells(ok[y], bins)
    fmt, fn = _REDUCERS[reduce]
    table = (
        pd.DataFrame({"i": cx.codes, "j": cy.codes, "v": ok[metric].astype(float).to_numpy()})
        .groupby(["j", "i"])["v"]
        .agg(fn)
    )
    grid = np.full((cy.centres.size, cx.centres.size), np.nan)
    grid[table.index.get_level_values("j"), table.index.get_level_values("i")] = table.to_numpy()
    grid = np.ma.masked_invalid(grid * qm.factor)

    fig, ax = _new_axes(ax, (7.5, 5.6))
    mesh = ax.pcolormesh(cx.edges * qx.factor, cy.edges * qy.factor, grid, cmap="viridis", shading="flat")
    if cx.log:
        ax.set_xscale("log")
    if cy.log:
        ax.set_yscale("log")
    colour_label = fmt.format(qm.name) + (f" [{qm.unit}]" if qm.unit else "")
    fig.colorbar(mesh, ax=ax, label=colour_label)
    if grid.size <= 100:
        _annotate(ax, mesh, grid, cx, cy, qx.factor, qy.factor)
    ax.set_xlabel(label(x))
    ax.set_ylabel(label(y))
    ax.set_title(f"{fmt.format(qm.name)} per cell ({_runs_note(len(ok), left_out)})", fontsize="medium")
    return _save(fig, path)


def _annotate(ax: Axes, mesh: Any, grid: np.ma.MaskedArray, cx: _Cells, cy: _Cells, fx: float, fy: float) -> None:
    colors = mesh.cmap(mesh.norm(grid))
    for j in range(grid.shape[0]):
        for i in range(grid.shape[1]):
            if grid.mask is not np.ma.nomask and grid.mask[j, i]:
                continue
            ax.text(
                cx.centres[i] * fx,
                cy.centres[j] * fy,
                f"{grid[j, i]:.3g}",
                ha="center",
                va="center",
                fontsize="x-small",
                color=_text_color(colors[j, i]),
            )

