"""Sweeps on a Dask cluster: :func:`sweep` and :func:`sweep_frame`.

Use this module when a Dask cluster already exists (``dask-jobqueue`` on Slurm or PBS, a
Kubernetes cluster, ``dask worker`` processes on several machines) and the sweep is too big for
one machine. On one machine :func:`cushion.sweep` is the better tool: it already uses every
core, with no scheduler in between. For a batch scheduler without Dask, the command line's
``cushion sweep FILE --shard K/N --out DIR`` and ``cushion merge`` split a sweep into jobs
(see ``docs/clusters.md``).

>>> from dask.distributed import Client
>>> import cushion.dask
>>> client = Client("tcp://scheduler:8786")
>>> frame = cushion.dask.sweep("sweeps/design-space.toml", client=client)

The sweep is resolved on the client, into self-contained TOML text (its base scene inlined),
so bad input raises :class:`cushion.ConfigError` before anything is submitted and the workers
need no files: only the ``cushion`` package. The runs ``0..n`` are split into contiguous
ranges, one partition each (``dask.dataframe.from_map``); a partition is a pure function of its
range (no files, no side effects), so a task Dask runs twice (a retry, a lost worker) gives the
same rows, once. The rows equal those of :func:`cushion.sweep` row for row.

Dask is imported only here: ``import cushion`` works without it.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import pandas as pd

from . import _cushion
from ._sweep import config_arg, frame_from_ipc

if TYPE_CHECKING:
    import dask.dataframe as dd
    import distributed

__all__ = ["sweep", "sweep_frame"]

#: Partitions per worker thread by default: enough that a slow range does not leave the other
#: threads idle at the end, few enough that Dask's per-task overhead (about 1 ms) stays small.
PARTITIONS_PER_THREAD = 4


def _runs_frame(
    runs: range, text: str, threads: int | None, columns: Sequence[str] | None = None
) -> pd.DataFrame:
    """Runs ``runs`` of the resolved sweep ``text``: one partition of :func:`sweep_frame`.

    A pure function of its arguments: nothing is read or written. The index is the run
    numbers (as the partition's divisions say), and ``run`` stays a column. ``columns``
    selects columns (Dask's optimizer passes it when only some are used).
    """
    frame = frame_from_ipc(_cushion.sweep_runs(text, runs.start, runs.stop, threads))
    frame.index = pd.Index(frame["run"].to_numpy(), dtype="int64")
    if columns is not None:
        frame = frame[list(columns)]
    return frame


def _ranges(n_runs: int, partitions: int) -> list[range]:
    """``range(n_runs)`` in ``partitions`` contiguous ranges whose lengths differ by at most 1
    (one empty range for an empty sweep)."""
    parts = max(1, min(partitions, n_runs))
    bounds = [n_runs * i // parts for i in range(parts + 1)]
    return [range(a, b) for a, b in zip(bounds[:-1], bounds[1:])]


def _current_client() -> distributed.Client | None:
    """The default ``distributed`` client, if distributed is installed and one exists."""
    try:
        from distributed import default_client
    except ImportError:
        return None
    try:
        return default_client()
    except ValueError:
        return None


def _worker_cores() -> int:
    """The cores this process may use (affinity and cgroup quota included): run on workers."""
    from dask.system import cpu_count

    return cpu_count()


def _cluster_threads(client: distributed.Client | None) -> int:
    """The task threads of the client's workers, all together (0 without a client or workers)."""
    if client is None:
        return 0
    try:
        return sum(client.nthreads().values())
    except Exception:  # a client that cannot reach its scheduler: fall back to this machine
        return 0


def _default_threads_per_task(client: distributed.Client | None) -> int:
    """Engine threads per task: each task's share of its machine's cores.

    A Dask worker runs ``nthreads`` tasks at once, and by Dask's own convention each task
    thread stands for one core; so each task's share of a machine is (cores of the machine) //
    (task threads of all workers on it). That is 1 for the usual set-ups (``dask worker`` and
    ``LocalCluster`` defaults, ``dask-jobqueue``'s ``cores=N``, several single-threaded
    worker processes per machine) and the machine's cores when a machine runs a single worker
    with a single task thread (one task at a time, the engine's threads then use every core).
    With several machines the smallest share is taken, as any task may land on any worker;
    with no client, or no workers yet (an adaptive cluster), 1.
    """
    if client is None:
        return 1
    try:
        from distributed.comm import get_address_host

        nthreads: dict[str, int] = client.nthreads()
        if not nthreads:
            return 1
        cores: dict[str, int] = client.run(_worker_cores)
        slots: dict[str, int] = {}
        host_cores: dict[str, int] = {}
        for addr, n in nthreads.items():
            host = get_address_host(addr)
            slots[host] = slots.get(host, 0) + n
            host_cores[host] = max(host_cores.get(host, 1), cores.get(addr, 1))
        return max(1, min(host_cores[h] // max(1, slots[h]) for h in slots))
    except Exception:  # workers that left or cannot answer: the safe choice
        return 1


def _build(
    config: str | os.PathLike[str] | Mapping[str, Any],
    client: distributed.Client | None,
    partitions: int | None,
    threads_per_task: int | None,
) -> dd.DataFrame:
    """:func:`sweep_frame` with defaults taken from ``client`` (``None``: no cluster)."""
    import dask
    import dask.dataframe as dd

    text, n_runs = _cushion.resolve_sweep(config_arg(config))
    if partitions is None:
        threads = _cluster_threads(client) or (os.cpu_count() or 1)
        partitions = PARTITIONS_PER_THREAD * threads
    elif isinstance(partitions, bool) or not isinstance(partitions, int) or partitions < 1:
        raise _cushion.ConfigError(f"partitions = {partitions!r}: expected an integer >= 1")
    if threads_per_task is None:
        threads_per_task = _default_threads_per_task(client)
    elif (
        isinstance(threads_per_task, bool)
        or not isinstance(threads_per_task, int)
        or threads_per_task < 1
    ):
        raise _cushion.ConfigError(
            f"threads_per_task = {threads_per_task!r}: expected an integer >= 1"
        )

    ranges = _ranges(n_runs, partitions)
    # Runs 0..0 compute nothing: the empty frame with the columns and dtypes of every partition.
    meta = _runs_frame(range(0, 0), text, 1)
    divisions = (
        tuple(r.start for r in ranges) + (ranges[-1].stop - 1,) if n_runs > 0 else None
    )
    # Keep the engine's dtypes (those of cushion.sweep) rather than Dask's string conversion,
    # so that a computed frame equals the local one dtype for dtype.
    with dask.config.set({"dataframe.convert-string": False}):
        return dd.from_map(
            _runs_frame,
            ranges,
            args=(text, threads_per_task),
            meta=meta,
            divisions=divisions,
            label="cushion-sweep",
            enforce_metadata=False,
        )


def sweep_frame(
    config: str | os.PathLike[str] | Mapping[str, Any],
    *,
    partitions: int | None = None,
    threads_per_task: int | None = None,
) -> dd.DataFrame:
    """A sweep as a lazy Dask DataFrame: one partition per contiguous range of runs.

    Parameters
    ----------
    config
        A sweep file (TOML) or a dict of the same shape, as :func:`cushion.sweep` takes. It is
        resolved here, on the client: a relative ``scene`` path is read now (relative to the
        sweep file, or to the working folder for a dict), and the workers get the sweep as
        text, needing no files.
    partitions
        How many run ranges (tasks). Default: 4 per worker thread of the current
        ``distributed`` client, or 4 per core of this machine without one. Never more than
        the run count, at least 1; the ranges' lengths differ by at most one run.
    threads_per_task
        Engine threads each task uses. Default: the task's share of its machine's cores, i.e.
        1 when workers run several task threads (each task is then its own parallel unit, as
        Dask assumes), and the machine's cores when a machine runs one worker with one task
        thread. The rows do not depend on it.

    Returns
    -------
    dask.dataframe.DataFrame
        The columns and dtypes of :func:`cushion.sweep` (``run``, one per axis, the summary
        fields; strings are not converted by Dask's ``dataframe.convert-string``). The
        index is the run number (``run`` is also a column), with known divisions: partition
        ``k`` holds runs ``divisions[k]`` onwards. An empty sweep gives one empty partition.

    Raises
    ------
    FileNotFoundError
        ``config`` names a sweep file that does not exist (or another :class:`OSError` for one
        that cannot be read), before anything is submitted.
    cushion.ConfigError
        Bad config (unknown key, empty axis, missing scene file named in it, ...) or a bad
        argument, before anything is submitted.

    Notes
    -----
    Each partition is a pure function of its run range (no files, no side effects), so a task
    that Dask runs twice gives the same rows once.
    """
    return _build(config, _current_client(), partitions, threads_per_task)


def sweep(
    config: str | os.PathLike[str] | Mapping[str, Any],
    *,
    client: distributed.Client | None = None,
    partitions: int | None = None,
    threads_per_task: int | None = None,
) -> pd.DataFrame:
    """Run a sweep on a Dask cluster and return one row per run, as :func:`cushion.sweep` does.

    Parameters
    ----------
    config
        A sweep file (TOML) or a dict of the same shape (see :func:`sweep_frame`).
    client
        The ``distributed`` client to compute on. Default: the current client if there is one,
        else Dask's default scheduler.
    partitions, threads_per_task
        As in :func:`sweep_frame` (defaults taken from ``client``'s workers).

    Returns
    -------
    pandas.DataFrame
        Sorted by ``run``, index ``0..n-1``: equal row for row (and dtype for dtype) to
        ``cushion.sweep(config)``.

    Raises
    ------
    FileNotFoundError
        ``config`` names a sweep file that does not exist (another :class:`OSError` for one that
        cannot be read), before anything is submitted.
    cushion.ConfigError
        Bad config, before anything is submitted.
    Exception
        An error in a task is raised here with its original type (Dask re-raises it).
    """
    import dask

    if client is None:
        client = _current_client()
    frame = _build(config, client, partitions, threads_per_task)
    if client is not None:
        (result,) = client.compute([frame], sync=True)
    else:
        (result,) = dask.compute(frame)
    return result.sort_values("run", kind="stable").reset_index(drop=True)
