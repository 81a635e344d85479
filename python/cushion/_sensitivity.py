"""Global sensitivity: :func:`sensitivity` answers "which inputs drive each output, alone and
through which interactions?" with Sobol indices computed by the engine (docs/sensitivity.md)."""

from __future__ import annotations

import os
from typing import Any, Mapping, Sequence

import pandas as pd

from . import _cushion
from ._args import path_or_dict
from ._progress import Progress, progress_for
from ._sweep import _git_commit, frame_from_ipc


def sensitivity(
    config: str | os.PathLike[str] | Mapping[str, Any],
    *,
    outputs: Sequence[str] | None = None,
    threads: int | None = None,
    progress: bool | Progress | None = None,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
) -> pd.DataFrame:
    """Sobol indices of a saltelli sweep's outputs: S1, ST and S2 with bootstrap intervals.

    The sweep (``[sampling] mode = "saltelli"``) runs through the same engine as
    :func:`cushion.sweep`; the estimators are SALib's (``SALib.analyze.sobol``), computed in
    Rust for every output at once, in parallel. The same file gives the same frame on any
    number of threads.

    Parameters
    ----------
    config
        A sweep file (TOML, as ``cushion sensitivity`` reads) or a dict of the same shape, with
        ``{"sampling": {"mode": "saltelli", "samples": N, "second_order": True, "seed": 0}}``,
        ``range`` axes only (optionally with ``dist``: ``"normal"``, ``"lognormal"``,
        ``"triangular"``, ...), and optionally ``{"sensitivity": {"outputs": [...],
        "resamples": 1000, "conf_level": 0.95, "seed": 0, "on_failed": "stop" or
        "drop_base_point"}}``.
    outputs
        The summary fields to analyse (overrides ``[sensitivity] outputs``; default: every
        numeric field).
    threads
        Worker threads (default: every core). The answer does not depend on it.
    progress
        ``None``: a progress bar in a terminal or notebook; ``True``: always; ``False``: none;
        or a callable ``progress(done, total)``.
    out
        Also write every file ``cushion sensitivity --out`` writes into this folder
        (``summary.parquet``, ``provenance.json``, ``sensitivity.parquet``,
        ``sensitivity.csv``, ``sensitivity.svg``, ...).
    resume
        With ``out``: continue the study interrupted there (Ctrl-C, a crash). The runs of the
        chunks already written are kept, the sweep file must be unchanged, and the analysis
        reads every run.

    Returns
    -------
    pandas.DataFrame
        The long frame of ``sensitivity.parquet``: ``output``, ``input`` (``S1`` and ``ST``
        rows), ``input_1`` and ``input_2`` (``S2`` rows), ``index`` (``"S1"``, ``"ST"``,
        ``"S2"``; ``"constant"`` for an output that takes one value on every run, ``value``
        being it; ``"not_finite"`` for an output missing on some runs, ``value`` being how
        many), ``value`` and ``conf`` (the interval's half-width).

    Raises
    ------
    FileNotFoundError
        ``config`` names a file that does not exist.
    cushion.ConfigError
        Bad input, before any run: the message names the key, the value and what is allowed.
    RuntimeError
        Runs did not end ``ok`` and ``on_failed = "stop"`` (the message names how many and
        their inputs).
    KeyboardInterrupt
        Ctrl-C stops the runs within one chunk; with ``out``, ``resume=True`` continues.
    """
    if isinstance(outputs, str):
        raise _cushion.ConfigError(f"outputs = {outputs!r}: expected a list of summary field names")
    callback, close = progress_for(progress, "cushion sensitivity")
    try:
        ipc = _cushion.sensitivity(
            path_or_dict(config, "config", "a path to a sweep file (TOML) or a dict of the same shape"),
            None if outputs is None else [str(o) for o in outputs],
            threads,
            None if out is None else os.fspath(out),
            resume,
            callback,
            _git_commit() if out is not None else None,
        )
    finally:
        close()
    return frame_from_ipc(ipc)
