"""`cushion.sweep` against `cushion sweep`: the same rows as `summary.parquet`, the same files
with `out`, resume, progress, the GIL released (two threads overlap), and Ctrl-C."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import pandas as pd
import pytest

import cushion
from conftest import ROOT, copy_sweep, interrupt

# Short scenes (t_end 0.12 s), two modules: a few hundred runs a second per core.
SMALL = {
    "name": "small",
    "scene": {"t_end": 0.12, "solver": {"rtol": 1e-5}},
    "sampling": {"mode": "sobol", "samples": 64, "seed": 3},
    "axis": [
        {"key": "robot.dead_time", "range": [0.0, 0.1]},
        {"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"},
        {"key": "object.mass", "range": [0.05, 1.0]},
        {"key": "module", "values": ["hydraulic", "bistable"]},
    ],
    "output": {"chunk_size": 16},
}

SMALL_TOML = """
name = "small"
[scene]
t_end = 0.12
[scene.solver]
rtol = 1e-5
[sampling]
mode = "sobol"
samples = 64
seed = 3
[[axis]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[axis]]
key = "hydraulic.gas_pressure"
range = [300.0, 1e5]
scale = "log"
[[axis]]
key = "object.mass"
range = [0.05, 1.0]
[[axis]]
key = "module"
values = ["hydraulic", "bistable"]
[output]
chunk_size = 16
"""


def cli_sweep(cli, path, out):
    cli("sweep", path, "--out", out, "--quiet")
    return pd.read_parquet(out / "summary.parquet")


def test_a_sweep_file_gives_the_rows_of_summary_parquet(cli, tmp_path):
    path = copy_sweep(tmp_path, "paper.toml")
    want = cli_sweep(cli, path, tmp_path / "cli")
    got = cushion.sweep(path, progress=False)
    pd.testing.assert_frame_equal(got, want, check_exact=True)
    assert list(got.columns[:3]) == ["run", "module", "robot.dead_time"]
    assert (got.status == "ok").all() and len(got) == 6


def test_a_dict_equals_the_same_sweep_as_a_file(cli, tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL_TOML)
    want = cli_sweep(cli, path, tmp_path / "cli")
    pd.testing.assert_frame_equal(cushion.sweep(SMALL, progress=False), want, check_exact=True)
    pd.testing.assert_frame_equal(cushion.sweep(path, threads=1, progress=False), want, check_exact=True)
    assert len(want) == 64 and set(want.module) == {"hydraulic", "bistable"}


def test_out_writes_every_file_the_command_writes(cli, tmp_path):
    path = copy_sweep(tmp_path, "paper.toml")
    cli_sweep(cli, path, tmp_path / "cli")
    frame = cushion.sweep(path, out=tmp_path / "py", progress=False)
    names = lambda d: sorted(p.name for p in d.iterdir() if not p.name.startswith("."))
    assert names(tmp_path / "py") == names(tmp_path / "cli")
    for f in ("summary.csv", "summary.parquet", "trajectories.mcap", "sweep.toml"):
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    pd.testing.assert_frame_equal(frame, pd.read_parquet(tmp_path / "py" / "summary.parquet"))
    prov = json.loads((tmp_path / "py" / "provenance.json").read_text())
    assert prov["runs_in_output"] == 6 and prov["invocations"] == 1
    # resuming a finished sweep computes nothing and gives the same rows
    again = cushion.sweep(path, out=tmp_path / "py", resume=True, progress=False)
    pd.testing.assert_frame_equal(again, frame)


def test_progress_reaches_the_total():
    seen = []
    cushion.sweep(SMALL, progress=lambda done, total: seen.append((done, total)), threads=1)
    assert seen and seen[-1] == (64, 64)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


def _long_sweep(samples: int) -> dict:
    return {**SMALL, "sampling": {"mode": "sobol", "samples": samples, "seed": 5}, "output": {"chunk_size": 64}}


def test_two_threads_sweep_in_parallel():
    """The GIL is released while the engine runs: two Python threads, each running a
    one-thread sweep, are in progress at once. Each reports its progress as it goes (the
    waiting thread takes the GIL only for that, every 100 ms); a report of one sweep falls
    between two unfinished reports of the other. Were the GIL held through the engine's work,
    the second sweep could not run its Python until the first were done. An order of
    events, not a time, so it does not depend on what else the machine runs."""
    config = _long_sweep(8192)
    alone = cushion.sweep(config, threads=1, progress=False)
    reports = []  # (sweep, done, total), in the order made
    lock = threading.Lock()
    results = {}

    def one(name):
        def progress(done, total):
            with lock:
                reports.append((name, done, total))

        results[name] = cushion.sweep(config, threads=1, progress=progress)

    threads = [threading.Thread(target=one, args=(n,)) for n in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results.values():
        pd.testing.assert_frame_equal(r, alone)

    def running(name):
        """Positions of the reports of `name` made while it was under way."""
        return [i for i, (n, done, total) in enumerate(reports) if n == name and 0 < done < total]

    def inside(name, other):
        mine = running(name)
        return bool(mine) and any(mine[0] < i < mine[-1] for i in running(other))

    assert inside("a", "b") or inside("b", "a"), reports


def test_ctrl_c_stops_a_sweep_and_resume_finishes_it(tmp_path):
    config = _long_sweep(4096)
    out = tmp_path / "out"
    # wait until a few chunks are done, then press Ctrl-C
    status, rest, err = interrupt("sweep", config, out, after=256)
    assert status == 3 and "interrupted" in rest, (status, rest, err)
    assert not (out / "summary.parquet").exists()
    chunks = sorted((out / ".sweep").glob("chunk-*.parquet"))
    assert chunks, "the finished chunks are kept"

    frame = cushion.sweep(config, out=out, resume=True, progress=False)
    whole = cushion.sweep(config, progress=False)
    pd.testing.assert_frame_equal(frame, whole, check_exact=True)
    assert frame.run.is_unique and len(frame) == 4096
    prov = json.loads((out / "provenance.json").read_text())
    assert prov["invocations"] == 2
    assert 0 < prov["runs_computed_now"] <= 4096 - 64 * len(chunks)


def test_a_progress_bar_only_where_asked_or_seen(capfd):
    cushion.sweep(SMALL, progress=True)
    err = capfd.readouterr().err
    assert "cushion sweep" in err and "64/64" in err
    # progress=None: standard error is not a terminal under pytest, and no notebook runs
    cushion.sweep(SMALL, progress=None)
    cushion.sweep(SMALL, progress=False)
    assert capfd.readouterr().err == ""
