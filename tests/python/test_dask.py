"""`cushion.dask` on a two-process LocalCluster: the rows equal the local `cushion.sweep` row for
row, whatever the partitioning; a task run twice (a retry, a lost worker) gives its rows once;
bad input raises `ConfigError` on the client before anything is submitted."""

from __future__ import annotations

import os
import shutil
from types import SimpleNamespace

import pandas as pd
import pytest

import cushion
from cushion import _cushion
from conftest import ROOT

distributed = pytest.importorskip("distributed")
dd = pytest.importorskip("dask.dataframe")

import cushion.dask as cdask  # noqa: E402  (after the skips: it needs dask)

# 20 dead times x 3 modules = 60 runs of 0.1 s each: milliseconds of compute.
GRID = {
    "name": "grid",
    "set": {"t_end": 0.1},
    "sampling": {"mode": "grid"},
    "axis": [
        {"key": "robot.dead_time", "linspace": [0.0, 0.07, 20]},
        {"key": "module", "values": ["hydraulic", "bistable", "rigid"]},
    ],
}

SOBOL = {
    "name": "sobol",
    "set": {"t_end": 0.1},
    "sampling": {"mode": "sobol", "samples": 48, "seed": 3},
    "axis": [
        {"key": "robot.dead_time", "range": [0.0, 0.05]},
        {"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"},
        {"key": "module", "values": ["hydraulic", "bistable"]},
    ],
}


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    c = distributed.Client(cluster)
    try:
        yield c
    finally:
        c.close()
        cluster.close()


def local(config) -> pd.DataFrame:
    return cushion.sweep(config, progress=False)


def assert_same(frame: pd.DataFrame, config) -> None:
    """Equal to the local sweep row for row, value for value, dtype for dtype."""
    assert frame["run"].is_unique
    pd.testing.assert_frame_equal(frame, local(config), check_exact=True)


def frame_of(func, config, partitions: int):
    """As sweep_frame builds it, with another partition function (same arguments)."""
    import dask

    text, n = _cushion.resolve_sweep(config)
    meta = cdask._runs_frame(range(0, 0), text, 1)
    with dask.config.set({"dataframe.convert-string": False}):
        return dd.from_map(
            func, cdask._ranges(n, partitions), args=(text, 1), meta=meta, enforce_metadata=False
        )


class GraphCounter(distributed.diagnostics.plugin.SchedulerPlugin):
    """Counts the graphs submitted to the scheduler."""

    def __init__(self) -> None:
        self.graphs = 0

    def update_graph(self, scheduler, **kwargs) -> None:
        self.graphs += 1


@pytest.mark.parametrize("config", [GRID, SOBOL], ids=["grid", "sobol"])
def test_equals_the_local_sweep_with_uneven_partitions(client, config):
    frame = cdask.sweep_frame(config, partitions=7)
    assert frame.npartitions == 7
    assert frame.known_divisions
    assert list(frame.dtypes) == list(local(config).dtypes)
    assert_same(cdask.sweep(config, client=client, partitions=7), config)


def test_partitions_are_contiguous_ranges_indexed_by_run(client):
    frame = cdask.sweep_frame(GRID, partitions=7)
    lengths = [len(p) for p in client.compute(frame.to_delayed(), sync=True)]
    assert sum(lengths) == 60 and max(lengths) - min(lengths) <= 1
    # divisions are run numbers, and the index is the run: .loc finds runs
    part = frame.loc[17:25].compute()
    assert list(part.index) == list(part["run"]) == list(range(17, 26))
    # the optimizer's column projection reaches the partitions
    assert list(frame[["run", "status"]].compute().columns) == ["run", "status"]


def test_a_sweep_file_with_a_relative_scene_from_elsewhere(client, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the workers never see sweeps/scenes: the client inlines it
    path = ROOT / "sweeps" / "paper.toml"
    assert_same(cdask.sweep(path, client=client), path)
    assert_same(cdask.sweep(str(path)), str(path))  # the default client


def test_a_dict_with_a_scene_path_relative_to_the_clients_folder(client, tmp_path, monkeypatch):
    shutil.copytree(ROOT / "sweeps" / "scenes", tmp_path / "scenes")
    monkeypatch.chdir(tmp_path)
    config = dict(GRID, scene="scenes/paper-bistable-dt10.toml")
    assert_same(cdask.sweep(config, client=client, partitions=3), config)


def test_computing_twice_and_running_a_range_twice_give_the_same_rows(client):
    frame = cdask.sweep_frame(GRID, partitions=5)
    first, second = (
        f.sort_values("run").reset_index(drop=True) for f in (frame.compute(), frame.compute())
    )
    pd.testing.assert_frame_equal(first, second, check_exact=True)
    assert_same(first, GRID)
    # one range, run twice as separate tasks (pure=False), on both workers
    text, _ = _cushion.resolve_sweep(GRID)
    workers = list(client.nthreads())
    futures = [
        client.submit(cdask._runs_frame, range(10, 22), text, 1, pure=False, workers=[w])
        for w in workers
    ]
    a, b = client.gather(futures)
    pd.testing.assert_frame_equal(a, b, check_exact=True)


def test_a_retried_task_gives_its_rows_once(client, tmp_path):
    flag = tmp_path / "failed-once"

    # Defined here, so cloudpickle sends it by value (workers cannot import this test module).
    def flaky(runs, text, threads):
        rows = cdask._runs_frame(runs, text, threads)
        if 20 in runs and not os.path.exists(flag):
            open(flag, "w").close()
            raise OSError("lost after computing its rows")
        return rows

    frame = frame_of(flaky, GRID, 6)
    result = client.compute(frame, retries=1).result()
    assert flag.exists()  # the first attempt failed, the retry ran
    assert_same(result.sort_values("run").reset_index(drop=True), GRID)


def test_a_task_whose_worker_dies_is_rerun_once(client, tmp_path):
    flag = tmp_path / "died-once"

    def dies_once(runs, text, threads):
        rows = cdask._runs_frame(runs, text, threads)
        if 40 in runs and not os.path.exists(flag):
            open(flag, "w").close()
            os._exit(1)  # the worker process dies holding the rows; the nanny restarts it
        return rows

    frame = frame_of(dies_once, GRID, 6)
    try:
        result = client.compute(frame).result(timeout=60)
    finally:
        client.wait_for_workers(2, timeout=60)
    assert flag.exists()
    assert_same(result.sort_values("run").reset_index(drop=True), GRID)


def test_bad_config_raises_on_the_client_before_any_task(client, tmp_path):
    counter = GraphCounter()
    scheduler = client.cluster.scheduler  # LocalCluster's scheduler lives in this process
    scheduler.add_plugin(counter, name="graph-counter")
    try:
        check_bad_input_raises(client, tmp_path)
        assert counter.graphs == 0  # nothing was submitted
        cdask.sweep(GRID, client=client, partitions=2)
        assert counter.graphs == 1  # ... while a good sweep is seen
    finally:
        scheduler.remove_plugin("graph-counter")


def check_bad_input_raises(client, tmp_path):
    bad_axis = dict(GRID, axis=[{"key": "robot.dead_tim", "values": [0.0, 0.01]}])
    with pytest.raises(cushion.ConfigError, match=r"robot\.dead_tim"):
        cdask.sweep(bad_axis, client=client)
    with pytest.raises(cushion.ConfigError, match=r"robot\.dead_tim"):
        cdask.sweep_frame(bad_axis)
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        cdask.sweep(tmp_path / "nope.toml", client=client)
    with pytest.raises(cushion.ConfigError, match="config"):
        cdask.sweep(42, client=client)
    for kwargs in ({"partitions": 0}, {"partitions": 2.5}, {"threads_per_task": 0}):
        with pytest.raises(cushion.ConfigError, match=next(iter(kwargs))):
            cdask.sweep(GRID, client=client, **kwargs)


def test_a_workers_error_keeps_its_type(client):
    text, n = _cushion.resolve_sweep(GRID)
    future = client.submit(cdask._runs_frame, range(n - 2, n + 3), text, 1)
    with pytest.raises(cushion.ConfigError, match="run count"):
        future.result()


@pytest.mark.parametrize("partitions", [1, 60, 500])
def test_partition_counts(client, partitions):
    frame = cdask.sweep_frame(GRID, partitions=partitions)
    assert frame.npartitions == min(partitions, 60)
    assert_same(cdask.sweep(GRID, client=client, partitions=partitions), GRID)


def test_a_single_run_and_the_default_partitioning(client):
    one = dict(GRID, axis=[{"key": "module", "values": ["rigid"]}])
    frame = cdask.sweep_frame(one, partitions=8)
    assert frame.npartitions == 1 and frame.divisions == (0, 0)
    assert_same(cdask.sweep(one, client=client, partitions=8), one)
    # default: 4 per worker thread (2 here), never more than the runs
    assert cdask.sweep_frame(GRID).npartitions == 8
    assert cdask.sweep_frame(one).npartitions == 1
    assert_same(cdask.sweep(GRID), GRID)


def test_an_empty_sweep_would_be_one_empty_partition():
    # The engine refuses an empty sweep (an empty axis, samples = 0); the split stays total.
    assert cdask._ranges(0, 8) == [range(0, 0)]
    assert cdask._ranges(5, 8) == [range(i, i + 1) for i in range(5)]
    assert cdask._ranges(10, 3) == [range(0, 3), range(3, 6), range(6, 10)]
    text, _ = _cushion.resolve_sweep(GRID)
    empty = cdask._runs_frame(range(0, 0), text, 1)
    assert empty.empty and list(empty.columns) == list(local(GRID).columns)


def test_threads_per_task_is_each_tasks_share_of_its_machine(client):
    assert cdask._default_threads_per_task(client) == 1  # 2 one-thread workers on one machine
    assert cdask._default_threads_per_task(None) == 1

    def fake(workers: dict[str, tuple[int, int]]):  # address -> (task threads, cores)
        return SimpleNamespace(
            nthreads=lambda: {a: t for a, (t, _) in workers.items()},
            run=lambda f: {a: c for a, (_, c) in workers.items()},
        )

    assert cdask._default_threads_per_task(fake({"tcp://a:1": (1, 8)})) == 8
    assert cdask._default_threads_per_task(fake({"tcp://a:1": (8, 8)})) == 1
    assert cdask._default_threads_per_task(fake({"tcp://a:1": (1, 8), "tcp://a:2": (1, 8)})) == 4
    assert cdask._default_threads_per_task(fake({"tcp://a:1": (1, 8), "tcp://b:1": (1, 4)})) == 4
    assert cdask._default_threads_per_task(fake({})) == 1
    # the rows do not depend on it
    assert_same(cdask.sweep(GRID, client=client, partitions=3, threads_per_task=2), GRID)
