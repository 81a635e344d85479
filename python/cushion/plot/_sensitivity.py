"""Sobol indices (:func:`cushion.sensitivity`'s long frame), as the command's
``sensitivity.svg`` draws them: per output, S1 and ST of each input with their intervals, and
the S2 matrix as a heat map."""

from __future__ import annotations

import os
from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ._units import _save

_S1, _ST = "#1f77b4", "#ff7f0e"


def sensitivity(
    frame: pd.DataFrame,
    path: str | os.PathLike[str] | None = None,
    *,
    outputs: Sequence[str] | None = None,
    max_outputs: int = 4,
) -> Figure:
    """S1 and ST per input with their intervals, one row of panels per output, and beside each
    the S2 matrix as a heat map (when the frame has S2 rows).

    Parameters
    ----------
    frame
        The long frame of :func:`cushion.sensitivity` (or ``sensitivity.parquet`` read back).
    path
        Write the figure there too (``.png``, ``.svg``, ``.pdf``).
    outputs
        The outputs to draw (default: the first ``max_outputs`` that vary over the sample).
    max_outputs
        The most outputs drawn when ``outputs`` is not given.
    """
    varying = [o for o in dict.fromkeys(frame["output"]) if (frame[frame["output"] == o]["index"] == "ST").any()]
    chosen = list(outputs) if outputs is not None else varying[:max_outputs]
    missing = [o for o in chosen if o not in varying]
    if missing:
        raise ValueError(f"outputs: no indices for {', '.join(missing)} (constant, not finite or absent)")
    if not chosen:
        raise ValueError("no output varies over the sample: nothing to draw")
    has_s2 = bool((frame["index"] == "S2").any())
    ncols = 2 if has_s2 else 1
    fig, axes = plt.subplots(
        len(chosen),
        ncols,
        figsize=(5.5 * ncols + 0.5, 3.2 * len(chosen)),
        layout="constrained",
        squeeze=False,
        gridspec_kw={"width_ratios": [3, 2] if has_s2 else [1]},
    )
    for row, name in enumerate(chosen):
        f = frame[frame["output"] == name]
        s1 = f[f["index"] == "S1"].set_index("input")
        st = f[f["index"] == "ST"].set_index("input")
        inputs = list(st.index)
        x = np.arange(len(inputs))
        ax = axes[row][0]
        w = 0.38
        ax.bar(x - w / 2, s1.loc[inputs, "value"], w, yerr=s1.loc[inputs, "conf"], color=_S1, label="S1", capsize=3)
        ax.bar(x + w / 2, st.loc[inputs, "value"], w, yerr=st.loc[inputs, "conf"], color=_ST, label="ST", capsize=3)
        ax.set_xticks(x, [k.rsplit(".", 1)[-1] for k in inputs])
        ax.axhline(0.0, color="black", linewidth=0.6)
        ax.set_ylabel("Sobol index [-]")
        ax.set_title(f"{name}: S1 and ST")
        ax.legend(loc="upper right", fontsize="small")
        if has_s2:
            ax2 = axes[row][1]
            d = len(inputs)
            m = np.full((d, d), np.nan)
            for _, r in f[f["index"] == "S2"].iterrows():
                j, k = inputs.index(r["input_1"]), inputs.index(r["input_2"])
                m[j, k] = m[k, j] = r["value"]
            lim = max(float(np.nanmax(np.abs(m))) if np.isfinite(m).any() else 0.0, 1e-12)
            im = ax2.imshow(m, cmap="RdBu_r", vmin=-lim, vmax=lim)
            for j in range(d):
                for k in range(d):
                    if j != k and np.isfinite(m[j, k]):
                        ax2.text(k, j, f"{m[j, k]:.3f}", ha="center", va="center", fontsize=8)
            short = [k.rsplit(".", 1)[-1] for k in inputs]
            ax2.set_xticks(range(d), short, rotation=30, ha="right")
            ax2.set_yticks(range(d), short)
            ax2.set_title(f"{name}: S2")
            fig.colorbar(im, ax=ax2, shrink=0.8)
    return _save(fig, path)
