"""Design questions: :func:`design` answers "which design keeps every limit for every
condition?" with a searched worst case, a refined feasible region and a verified answer."""

from __future__ import annotations

import json
import os
from typing import Any, Mapping

import pandas as pd

from . import _cushion
from ._args import path_or_dict
from ._progress import Progress, progress_for
from ._sweep import _git_commit, frame_from_ipc


class Design:
    """An answered design question (what :func:`cushion.design` returns).

    Attributes
    ----------
    points : pandas.DataFrame
        One row per evaluated design point (the columns of ``design.parquet``): the design
        keys; for each limited metric its worst value over the ``for_all`` box,
        ``<metric>.worst``, and the witness, ``<metric>.at.<key>`` (the conditions where it
        happens); ``feasible``; ``margin`` (the smallest relative distance of the worst cases
        to the limits, negative when one is violated); ``runs`` spent on the point.
    runs : pandas.DataFrame
        Every run made (the columns of ``runs.parquet``: ``stage`` (``search`` or ``verify``),
        the design and ``for_all`` keys, then a sweep's summary fields).
    best : dict
        ``answer.json``: the chosen design, its worst cases with their witnesses, its margin,
        the verification on the ``verify`` grid (``all_met``, the worst case found there), the
        runs spent and the wall time.
    out_dir : str or None
        The folder the files were written to (``out=``), else ``None``.
    """

    __slots__ = ("_answer", "_points", "_runs", "best")

    def __init__(self, answer: Any) -> None:
        self._answer = answer
        self._points: pd.DataFrame | None = None
        self._runs: pd.DataFrame | None = None
        self.best: dict[str, Any] = json.loads(answer.answer())

    @property
    def points(self) -> pd.DataFrame:
        if self._points is None:
            self._points = frame_from_ipc(self._answer.points())
        return self._points

    @property
    def runs(self) -> pd.DataFrame:
        if self._runs is None:
            self._runs = frame_from_ipc(self._answer.runs())
        return self._runs

    @property
    def design_keys(self) -> list[str]:
        """The design keys, in the file's order."""
        return list(self._answer.design_keys)

    @property
    def out_dir(self) -> str | None:
        return self._answer.out_dir

    def map_margin(self, frame: pd.DataFrame | Mapping[str, Any]) -> pd.Series:
        """The refined map's margin at each design point of ``frame`` (a DataFrame, or a dict of
        columns, with one column per design key): interpolated between the corners of the map
        cell the point falls in. Points outside the design box raise :class:`cushion.ConfigError`."""
        frame = pd.DataFrame(frame)
        missing = [k for k in self.design_keys if k not in frame.columns]
        if missing:
            raise _cushion.ConfigError(
                f"frame: no column {', '.join(missing)}; expected one per design key ({', '.join(self.design_keys)})"
            )
        rows = frame[self.design_keys].astype(object).values.tolist()
        return pd.Series(self._answer.map_margin(rows), index=frame.index, name="map_margin", dtype=float)

    def classify(self, frame: pd.DataFrame | Mapping[str, Any]) -> pd.Series:
        """Whether each design point of ``frame`` is feasible by the refined map (the map's
        margin there is at least 0; see :meth:`map_margin`). A boolean Series on ``frame``'s
        index."""
        return (self.map_margin(frame) >= 0.0).rename("feasible")

    def plot(self, path: str | os.PathLike[str] | None = None, **kwargs: Any) -> Any:
        """The design map (:func:`cushion.plot.design_map`); needs matplotlib."""
        from . import plot

        return plot.design_map(self, path, **kwargs)

    def __repr__(self) -> str:
        b = self.best
        design = ", ".join(f"{k} = {v}" for k, v in b["design"].items())
        verified = "verified" if b["verification"]["all_met"] else "NOT verified"
        return f"<cushion.Design {b['name']}: {design}; margin {b['margin']}; {verified}; {b['runs']['total']} runs>"


def design(
    config: str | os.PathLike[str] | Mapping[str, Any],
    *,
    threads: int | None = None,
    progress: bool | Progress | None = None,
    out: str | os.PathLike[str] | None = None,
) -> Design:
    """Answer a design question: which design keeps every limit for every condition?

    Parameters
    ----------
    config
        A design file (TOML, as ``cushion design`` reads) or a dict of the same shape:
        ``{"name": ..., "scene": ..., "set": {...}, "design": [{"key": ..., "range": [lo, hi]}
        or {"key": ..., "values": [...]}, ...], "for_all": [...], "limit": [{"metric": ...,
        "max": ..., "min": ..., "abs": True}, ...], "objective": {"minimize": metric},
        "search": {"resolution": 1/64, "tolerance": 1e-3, "verify": 41}}``. A relative
        ``scene`` in a dict is taken from the working folder.
    threads
        Worker threads (default: every core). The answer does not depend on it.
    progress
        ``None``: a progress bar in a terminal or notebook; ``True``: always; ``False``: none;
        or a callable ``progress(done, total)`` (the total grows with each refinement round).
    out
        Also write every file ``cushion design --out`` writes into this folder
        (``design.parquet``, ``runs.parquet``, ``answer.json``, ``design-map.svg``, ...).

    Returns
    -------
    Design
        ``.best`` (the answer), ``.points``, ``.runs``, ``.classify(frame)``, ``.plot()``.

    Raises
    ------
    FileNotFoundError
        ``config`` names a file that does not exist (another :class:`OSError` for one that
        cannot be read).
    cushion.ConfigError
        Bad input, before any run: the message names the key, the value and what is allowed.
    KeyboardInterrupt
        Ctrl-C stops the search within one batch of runs; with ``out``, nothing is written.
    """
    callback, close = progress_for(progress, "cushion design")
    try:
        answer = _cushion.design(
            path_or_dict(config, "config", "a path to a design file (TOML) or a dict of the same shape"),
            threads,
            None if out is None else os.fspath(out),
            callback,
            _git_commit() if out is not None else None,
        )
    finally:
        close()
    return Design(answer)
