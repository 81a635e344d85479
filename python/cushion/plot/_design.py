"""The design map of an answered design question (:func:`cushion.design`), as the command's
``design-map.svg`` draws it: over two design axes (the others at the chosen design) the refined
map's margin, feasible where it is at least 0, the boundary, the evaluated design points and the
chosen design; over one design axis, each worst case against it with its limits."""

from __future__ import annotations

import os
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import TwoSlopeNorm
from matplotlib.figure import Figure

from ._units import _save, label, quantity

_FEASIBLE, _INFEASIBLE, _BEST = "#2ca02c", "#d62728", "#000000"


def _range_keys(design: Any) -> list[str]:
    """Design keys whose values are numbers (a range), in the file's order."""
    pts = design.points
    return [k for k in design.design_keys if pd.api.types.is_numeric_dtype(pts[k])]


def _is_log_axis(values: pd.Series) -> bool:
    v = values.to_numpy(dtype=float)
    return bool(v.min() > 0 and v.max() / v.min() > 100.0)


def design_map(
    design: Any,
    path: str | os.PathLike[str] | None = None,
    *,
    x: str | None = None,
    y: str | None = None,
    resolution: int = 160,
) -> Figure:
    """Draw the feasible region of ``design`` (a :class:`cushion.Design`).

    With two or more numeric design keys: ``x`` and ``y`` (default: the first two) span the
    picture, every other design key held at the chosen design; the colour is the refined map's
    margin (green feasible, red not), the black line the boundary (margin 0), dots the evaluated
    design points in that slice, the star the chosen design. With one: each limited metric's
    worst case against the design key, the limits dashed, the chosen design marked.
    """
    keys = _range_keys(design)
    best = design.best
    if len(keys) >= 2 or (x is not None and y is not None):
        x = x or keys[0]
        y = y or [k for k in keys if k != x][0]
        return _save(_map(design, best, x, y, resolution), path)
    if len(keys) == 1:
        return _save(_worst_against(design, best, keys[0]), path)
    raise ValueError("design_map needs at least one numeric design key")


def _map(design: Any, best: dict[str, Any], x: str, y: str, n: int) -> Figure:
    pts = design.points
    xs, ys = pts[x], pts[y]
    logx, logy = _is_log_axis(xs), _is_log_axis(ys)
    gx = np.geomspace(xs.min(), xs.max(), n) if logx else np.linspace(xs.min(), xs.max(), n)
    gy = np.geomspace(ys.min(), ys.max(), n) if logy else np.linspace(ys.min(), ys.max(), n)
    X, Y = np.meshgrid(gx, gy)
    grid = pd.DataFrame({x: X.ravel(), y: Y.ravel()})
    for k in design.design_keys:
        if k not in (x, y):
            grid[k] = best["design"][k]
    margin = design.map_margin(grid).to_numpy().reshape(X.shape)
    # the slice: the evaluated points whose other design keys are the chosen design's
    on_slice = np.ones(len(pts), bool)
    for k in design.design_keys:
        if k not in (x, y):
            on_slice &= (pts[k] == best["design"][k]).to_numpy()
    fx, fy = quantity(x).factor, quantity(y).factor
    fig, ax = plt.subplots(figsize=(7.0, 5.4), layout="constrained")
    # the scale spans the feasible margins (often a few per cent) on both sides of 0, so the
    # feasible region reads green however thin its margin; larger violations saturate red
    lim = max(float(np.nanmax(margin)), 0.02)
    mesh = ax.pcolormesh(
        X * fx, Y * fy, np.clip(margin, -lim, lim), cmap="RdYlGn", norm=TwoSlopeNorm(0.0, -lim, lim), shading="auto"
    )
    fig.colorbar(mesh, ax=ax, label="margin (relative distance to the nearest limit)")
    ax.contour(X * fx, Y * fy, margin, levels=[0.0], colors="k", linewidths=1.2)
    sl = pts[on_slice]
    ax.scatter(
        sl[x] * fx, sl[y] * fy, s=7,
        c=np.where(sl["feasible"], _FEASIBLE, _INFEASIBLE), edgecolors="white", linewidths=0.3,
        label=f"{len(sl)} design points evaluated", zorder=3,
    )
    ax.scatter(
        [best["design"][x] * fx], [best["design"][y] * fy], marker="*", s=220, c=_BEST,
        edgecolors="white", zorder=4, label="chosen design",
    )
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(label(x))
    ax.set_ylabel(label(y))
    fixed = [f"{k} = {best['design'][k]}" for k in design.design_keys if k not in (x, y)]
    verified = "verified" if best["verification"]["all_met"] else "NOT verified"
    ax.set_title(f"{best['name']}: feasible region" + (f" ({', '.join(fixed)})" if fixed else "") + f"; {verified}")
    ax.legend(loc="best", fontsize=8)
    return fig


def _worst_against(design: Any, best: dict[str, Any], key: str) -> Figure:
    pts = design.points.sort_values(key)
    worst = best["worst"]
    fig, axes = plt.subplots(len(worst), 1, figsize=(7.0, 2.6 * len(worst)), sharex=True, layout="constrained", squeeze=False)
    fx = quantity(key).factor
    for ax, w in zip(axes[:, 0], worst):
        name, metric = w["name"], w["metric"]
        q = quantity(metric)
        ax.plot(pts[key] * fx, pts[f"{name}.worst"] * q.factor, ".-", lw=1, ms=3, label="worst case over the for_all box")
        lim = w.get("limit") or {}
        for end in ("max", "min"):
            v = lim.get(end)
            if v is not None:
                for s in ([v, -v] if lim.get("abs") else [v]):
                    ax.axhline(s * q.factor, color=_INFEASIBLE, ls="--", lw=1)
        if w["value"] is not None:
            ax.plot([best["design"][key] * fx], [w["value"] * q.factor], "*", ms=13, c=_BEST, label="chosen design")
        ax.set_ylabel(label(metric))
        ax.legend(loc="best", fontsize=8)
    axes[-1, 0].set_xlabel(label(key))
    if _is_log_axis(pts[key]):
        axes[-1, 0].set_xscale("log")
    axes[0, 0].set_title(f"{best['name']}: worst cases against {key}")
    return fig
