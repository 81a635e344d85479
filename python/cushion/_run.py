"""One run: :func:`simulate`, the :class:`Run` it returns, and :func:`read_mcap`."""

from __future__ import annotations

import os
from typing import Any, Mapping

import numpy as np
import pandas as pd

from . import _cushion
from ._args import path_or_dict

#: Trajectory columns, in the order of ``--csv`` (SI units: s, m, m/s, Pa, N), as the engine
#: names them for every output (one list, in the compiled module).
COLUMNS: tuple[str, ...] = _cushion.COLUMNS

_INDEX = {c: i for i, c in enumerate(COLUMNS)}
_EMPTY = np.empty(0)


class Run:
    """One simulated (or recorded) run.

    Attributes
    ----------
    summary : dict or None
        The summary with the names of ``cushion simulate --json`` (``status``, ``t_detect``,
        ``peak_robot_force``, ``object_final_velocity``, ..., ``stats`` nested). ``None`` for a
        run read back from MCAP, which records no summary.
    t, x_r, v_r, x_t, v_t, x_p, v_p, s, p1, F_c, F_r : numpy.ndarray
        The trajectory, one array per quantity (time s; positions m; speeds m/s; stroke
        ``s = x_r - x_t`` m; gas pressure ``p1`` Pa; contact force ``F_c`` and force on the
        robot ``F_r`` N): every solver step and event plus uniform samples, as ``--csv``
        writes them. NaN where the scene lacks the quantity (no object, no gas). Empty when
        the run was made with ``trajectory=False``.
    events : pandas.DataFrame
        The event log: ``t`` (s), ``event`` (``sensor``, ``brake``, ``object_contact_begin``,
        ...), ``direction`` (``"begin"``/``"end"`` for a phase that begins or ends, else
        ``""``), and the state at the event (the trajectory's columns).
    """

    __slots__ = ("summary", "_data", "_events", "_events_frame")

    def __init__(
        self,
        summary: dict[str, Any] | None,
        data: np.ndarray | Mapping[str, np.ndarray] | None,
        events: tuple[np.ndarray, list[str], np.ndarray] | Mapping[str, Any],
    ) -> None:
        """A run from its parts: the summary dict (or ``None``), the trajectory (an
        ``(11, n)`` array whose rows are :data:`COLUMNS`, or a dict of the columns, or
        ``None``), and the event log (``(times, names, states)`` with ``states`` an
        ``(n, 11)`` array, or a dict with ``t``, ``event`` and the state columns)."""
        self.summary = summary
        # (the exact types `simulate` passes are tested first: a check against the abstract
        # Mapping costs about a microsecond, a hundredth of a paper scene's run)
        if data is not None and type(data) is not np.ndarray and isinstance(data, Mapping):
            data = np.vstack([np.asarray(data[c], dtype=float) for c in COLUMNS])
        self._data = data
        if type(events) is not tuple and isinstance(events, Mapping):
            states = np.column_stack([np.asarray(events[c], dtype=float) for c in COLUMNS]).reshape(-1, len(COLUMNS))
            events = (np.asarray(events["t"], dtype=float), list(events["event"]), states)
        self._events = events
        self._events_frame: pd.DataFrame | None = None

    @property
    def status(self) -> str | None:
        """``ok``, ``max_steps``, ``step_too_small``, ``non_finite``, ``stiff`` or ``invalid``."""
        return None if self.summary is None else self.summary["status"]

    @property
    def stats(self) -> dict[str, Any] | None:
        """Solver statistics: ``steps``, ``rejected``, ``rhs_evals``, ``events``, ``stiff``,
        ``jacobians``, ``lu_decompositions`` and ``method_switches`` (the implicit method's work
        under ``rodas`` and ``auto``)."""
        return None if self.summary is None else self.summary["stats"]

    def __getattr__(self, name: str) -> np.ndarray:
        i = _INDEX.get(name)
        if i is not None:
            data = object.__getattribute__(self, "_data")
            return _EMPTY if data is None else data[i]
        raise AttributeError(f"'Run' object has no attribute {name!r}")

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(COLUMNS))

    @property
    def events(self) -> pd.DataFrame:
        if self._events_frame is None:
            t, names, states = self._events
            frame = pd.DataFrame({"t": t, "event": names, "direction": [_direction(n) for n in names]})
            for i, c in enumerate(COLUMNS[1:], start=1):
                frame[c] = states[:, i]
            self._events_frame = frame
        return self._events_frame

    def to_pandas(self) -> pd.DataFrame:
        """The trajectory as a DataFrame with the columns ``t, x_r, ..., F_r``."""
        return pd.DataFrame({c: getattr(self, c) for c in COLUMNS})

    def plot(self, path: str | os.PathLike[str] | None = None, **kwargs: Any):
        """The paper's figure 3 for this run (positions, velocities, gas pressure, forces;
        detection and brake marked); see :func:`cushion.plot.run`. Returns the figure, and
        writes it to ``path`` when given."""
        from . import plot

        return plot.run(self, path=path, **kwargs)

    def __repr__(self) -> str:
        n = len(self.t)
        if self.summary is None:
            return f"<cushion.Run recorded, {n} points, {len(self._events[0])} events>"
        s = self.summary
        return (
            f"<cushion.Run status={s['status']!r} peak_robot_force={s['peak_robot_force']:.4g} N "
            f"object_final_velocity={s['object_final_velocity']:.4g} m/s, {n} points>"
        )


def _direction(name: str) -> str:
    for d in ("begin", "end"):
        if name.endswith("_" + d):
            return d
    return ""


def _scene_arg(scene: Any) -> Any:
    if scene is None or isinstance(scene, _cushion.Scene):
        return scene
    return path_or_dict(
        scene, "scene", "a path to a scene file (TOML), a dict of scene keys, a cushion.Scene, or None"
    )


def simulate(
    scene: str | os.PathLike[str] | Mapping[str, Any] | _cushion.Scene | None = None,
    *,
    set: Mapping[str, Any] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    trajectory: bool = True,
    sample_interval: float | None = None,
) -> Run:
    """Simulate one scene.

    Parameters
    ----------
    scene
        A scene file (TOML), a dict of scene keys (``{"module": "bistable", "robot":
        {"dead_time": 0.01}}`` or ``{"robot.dead_time": 0.01}``), or ``None`` for the defaults
        (the paper's hydraulic scene, dead time 70 ms); or a :class:`cushion.Scene`, read and
        checked once, for many runs of one scene (reading a scene file costs about as much
        as a fifth of its run).
    set
        Overrides ``{"section.key": value}`` applied after ``scene``, in order (the keys of
        ``cushion simulate --set``; :func:`cushion.keys` lists them).
    rtol, atol, method
        Shorthands for ``solver.rtol``, ``solver.atol`` and ``solver.method``: ``"auto"``, the
        default (``"dp5"`` while the scene is not stiff, ``"rodas"`` while it is, e.g. a
        compressible liquid); ``"dp5"``, adaptive Dormand-Prince 5(4); ``"dop853"``,
        Dormand-Prince 8(5,3), for tight tolerances; ``"rodas"``, an implicit method for stiff
        scenes; ``"rk4"``, ``"euler"``, fixed step ``solver.fixed_step``.
    trajectory
        Record the trajectory (``False`` is faster when only the summary is wanted).
    sample_interval
        Besides every solver step and event, sample the trajectory every this many seconds of
        simulated time (default ``t_end / 2000``; ``0``: steps and events only).

    Returns
    -------
    Run
        Its ``status`` is ``"ok"`` or says how the run failed; a numerical failure is not an
        exception.

    Raises
    ------
    FileNotFoundError, PermissionError, IsADirectoryError
        ``scene`` names a file that cannot be read (an :class:`OSError`, as ``open`` raises).
    cushion.ConfigError
        Bad input: a file that is not a valid scene, an unknown key, a wrong type or value; the
        message names the key, the value and what is allowed.
    """
    summary, data, events = _cushion.simulate(
        _scene_arg(scene),
        None if set is None else dict(set),
        rtol,
        atol,
        method,
        trajectory,
        sample_interval,
    )
    return Run(summary, data, events)


def read_mcap(path: str | os.PathLike[str], run: int | None = None) -> Run:
    """Read a recorded run back from MCAP: a file of ``cushion simulate --mcap`` (``run=None``)
    or a sweep's ``trajectories.mcap`` (``run`` = the run number; ``None`` when it holds one
    run). The arrays and events equal those :func:`simulate` returned for that run; the
    summary is ``None`` (MCAP records no summary).

    A file that cannot be read raises :class:`FileNotFoundError` (or another :class:`OSError`);
    a file that is not MCAP an :class:`OSError`; a ``run`` the file does not hold
    :class:`cushion.ConfigError`."""
    data, events = _cushion.read_mcap(os.fspath(path), run)
    return Run(None, data, events)
