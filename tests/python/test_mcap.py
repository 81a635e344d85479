"""`cushion.read_mcap` reads a recorded run back: equal to what `simulate` returned for it,
whether written by `cushion simulate --mcap` or by a sweep; checked against the independent
`mcap` reader too."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
from mcap.reader import make_reader

import cushion
from conftest import ROOT, copy_sweep

COLUMNS = ["t", "x_r", "v_r", "x_t", "v_t", "x_p", "v_p", "s", "p1", "F_c", "F_r"]


def assert_same_run(a: cushion.Run, b: cushion.Run) -> None:
    for c in COLUMNS:
        assert np.array_equal(getattr(a, c), getattr(b, c), equal_nan=True), c
    pd.testing.assert_frame_equal(a.events, b.events, check_exact=True)


def test_a_recorded_scene_reads_back_as_simulated(cli, tmp_path):
    for scene in ("paper-bistable-dt10", "paper-rigid"):
        path = ROOT / "sweeps/scenes" / f"{scene}.toml"
        cli("simulate", path, "--mcap", tmp_path / f"{scene}.mcap")
        back = cushion.read_mcap(tmp_path / f"{scene}.mcap")
        assert back.summary is None and back.status is None
        assert_same_run(back, cushion.simulate(path))


def test_a_sweeps_recorded_runs_read_back_by_number(tmp_path):
    path = copy_sweep(tmp_path, "paper.toml")
    frame = cushion.sweep(path, out=tmp_path / "out", progress=False)
    mcap = tmp_path / "out" / "trajectories.mcap"
    assert cushion._cushion.recorded_runs(str(mcap)) == list(range(6))
    for run in (0, 3, 5):
        row = frame[frame.run == run].iloc[0]
        scene = ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"
        # sweeps/paper.toml samples recorded runs every 0.1 ms
        again = cushion.simulate(
            scene,
            set={"module": row["module"], "robot.dead_time": row["robot.dead_time"]},
            sample_interval=1e-4,
        )
        assert_same_run(cushion.read_mcap(mcap, run=run), again)
        assert again.summary["peak_robot_force"] == row["peak_robot_force"]


def test_the_independent_reader_sees_the_same_events(cli, tmp_path):
    cli("simulate", "--mcap", tmp_path / "d.mcap")
    run = cushion.read_mcap(tmp_path / "d.mcap")
    with open(tmp_path / "d.mcap", "rb") as f:
        msgs = [(c.topic, json.loads(m.data)) for _, c, m in make_reader(f).iter_messages()]
    events = [m for topic, m in msgs if topic == "/events"]
    states = [m for topic, m in msgs if topic == "/state"]
    assert [e["name"] for e in events] == list(run.events.event)
    assert [e["t"] for e in events] == list(run.events.t)
    assert [s["t"] for s in states] == list(run.t)
    assert [s["F_r"] for s in states] == list(run.F_r)
