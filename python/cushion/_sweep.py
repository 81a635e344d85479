"""Sweeps: :func:`sweep` runs a sweep file (or a dict of its shape) in parallel and returns
one row per run as a pandas DataFrame."""

from __future__ import annotations

import os
import subprocess
from typing import Any, Mapping

import pandas as pd
import pyarrow as pa

from . import _cushion
from ._args import path_or_dict
from ._progress import Progress, progress_for


def frame_from_ipc(data: bytes) -> pd.DataFrame:
    """An Arrow IPC stream of summary rows as a DataFrame (as pandas reads ``summary.parquet``)."""
    return pa.ipc.open_stream(data).read_all().to_pandas()


def config_arg(config: Any) -> Any:
    """A sweep config as the engine takes it: a path string or a plain dict."""
    return path_or_dict(config, "config", "a path to a sweep file (TOML) or a dict of the same shape")


def _git_commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"], capture_output=True, text=True, timeout=5, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return None
    commit = out.stdout.strip()
    return commit if out.returncode == 0 and commit else None


def sweep(
    config: str | os.PathLike[str] | Mapping[str, Any],
    *,
    threads: int | None = None,
    progress: bool | Progress | None = None,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
) -> pd.DataFrame:
    """Run a sweep: many scenes, in parallel, one summary row each.

    Parameters
    ----------
    config
        A sweep file (TOML, as ``cushion sweep`` takes), or a dict of the same shape:
        ``{"name": ..., "scene": path or dict of scene keys, "set": {"section.key": value},
        "sampling": {"mode": "grid" | "zip" | "lhs" | "sobol", ...}, "axis": [{"key": ...,
        "values": [...]}, ...], "output": {...}}``. A relative ``scene`` path in a dict is
        taken from the working folder.
    threads
        Worker threads (default: every core). The rows do not depend on it.
    progress
        ``None``: a progress bar in a terminal or notebook; ``True``: always; ``False``: none;
        or a callable ``progress(done, total)``.
    out
        Also write every file ``cushion sweep --out`` writes into this folder
        (``summary.parquet``, ``summary.csv``, ``provenance.json``, trajectories, charts).
    resume
        With ``out``: continue an interrupted sweep there, recomputing nothing finished.

    Returns
    -------
    pandas.DataFrame
        The columns and values of ``summary.parquet``: ``run``, one column per axis, then the
        summary fields (``status``, ``peak_robot_force``, ..., ``stats_steps``, ...).

    A sweep file that cannot be read raises :class:`FileNotFoundError` (or another
    :class:`OSError`); bad input :class:`cushion.ConfigError`, before any run. Ctrl-C stops the sweep
    within one chunk (``KeyboardInterrupt``); with ``out``, ``resume=True`` continues it. The
    GIL is released while the engine runs.
    """
    callback, close = progress_for(progress, "cushion sweep")
    try:
        data = _cushion.sweep(
            config_arg(config),
            threads,
            None if out is None else os.fspath(out),
            resume,
            callback,
            _git_commit() if out is not None else None,
        )
    finally:
        close()
    return frame_from_ipc(data)
