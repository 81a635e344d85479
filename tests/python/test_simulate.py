"""`cushion.simulate` against the command line: the same scene gives the same summary to the
bit (`--json`), the same trajectory samples (`--csv`) and the same events (`--mcap`)."""

from __future__ import annotations

import csv
import math
import pickle

import numpy as np
import pytest

import cushion
from conftest import ROOT, SCENES, same


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_summary_equals_the_command_line_json_to_the_bit(scene, cli_json):
    run = cushion.simulate(scene)
    assert same(run.summary, cli_json(scene))
    assert run.status == run.summary["status"] == "ok"
    assert run.stats == run.summary["stats"]


def test_overrides_shorthands_and_dict_scenes_equal_the_command_line(cli_json):
    want = cli_json(
        ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml",
        "--set", "module=bistable", "--set", "robot.dead_time=0.01",
        "--set", "solver.rtol=1e-8", "--set", "solver.atol=1e-11",
    )
    by_set = cushion.simulate(
        ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml",
        set={"module": "bistable", "robot.dead_time": 0.01, "solver.rtol": 1e-8, "solver.atol": 1e-11},
    )
    by_keywords = cushion.simulate(
        str(ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"),
        set={"module": "bistable", "robot.dead_time": 0.01},
        rtol=1e-8,
        atol=1e-11,
        method="dp5",
    )
    nested = cushion.load_scene(ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml")
    nested.update({"module": "bistable", "robot.dead_time": 0.01, "solver.rtol": 1e-8, "solver.atol": 1e-11})
    by_dict = cushion.simulate(nested)
    for r in (by_set, by_keywords, by_dict):
        assert same(r.summary, want)
    # a dict of sections, as a scene file's tables
    sections = {"module": "bistable", "robot": {"dead_time": 0.01}, "solver": {"rtol": 1e-8, "atol": 1e-11}}
    assert same(
        cushion.simulate(sections).summary,
        cli_json(
            "--set", "module=bistable", "--set", "robot.dead_time=0.01",
            "--set", "solver.rtol=1e-8", "--set", "solver.atol=1e-11",
        ),
    )


def test_numpy_scalars_are_taken_as_numbers(cli_json):
    run = cushion.simulate(set={"robot.dead_time": np.float64(0.01), "solver.max_steps": np.int64(100000)})
    assert same(run.summary, cli_json("--set", "robot.dead_time=0.01", "--set", "solver.max_steps=100000"))


def _csv_columns(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {h: np.array([float(r[i]) if r[i] != "" else math.nan for r in body]) for i, h in enumerate(header)}


@pytest.mark.parametrize("scene", ["paper-hydraulic-dt70", "paper-rigid"])
def test_trajectory_arrays_are_the_csv_samples(scene, cli, tmp_path):
    path = ROOT / "sweeps/scenes" / f"{scene}.toml"
    cli("simulate", path, "--csv", tmp_path / "t.csv")
    want = _csv_columns(tmp_path / "t.csv")
    run = cushion.simulate(path)
    frame = run.to_pandas()
    assert list(frame.columns) == list(want)
    for name, values in want.items():
        got = getattr(run, name)
        assert got.dtype == np.float64 and got.shape == values.shape
        assert np.array_equal(got, values, equal_nan=True), name
        assert np.array_equal(frame[name].to_numpy(), values, equal_nan=True)
    if scene == "paper-rigid":
        assert np.isnan(run.p1).all()  # no gas in a rigid module


def test_arrays_are_handed_over_without_a_copy():
    run = cushion.simulate()
    # views of one array built on the Rust vector: numpy owns none of the data, and at the
    # root of the views is the Rust container, not an array numpy copied into
    root = run.t
    while isinstance(root, np.ndarray):
        assert not root.flags.owndata
        root = root.base
    assert root is not None
    assert np.shares_memory(run.t.base, run.F_r)


def test_sample_interval_and_no_trajectory(cli, tmp_path):
    cli("simulate", "--sample-interval", "0", "--csv", tmp_path / "steps.csv")
    run = cushion.simulate(sample_interval=0)
    assert np.array_equal(run.t, _csv_columns(tmp_path / "steps.csv")["t"])
    fast = cushion.simulate(trajectory=False)
    assert fast.t.size == 0 and fast.to_pandas().empty
    assert same(fast.summary, run.summary)


def test_event_log(cli_json):
    run = cushion.simulate(ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml")
    ev = run.events
    assert list(ev.columns[:3]) == ["t", "event", "direction"]
    assert ev["t"].is_monotonic_increasing
    s = run.summary
    sensor = ev[ev.event == "sensor"]
    brake = ev[ev.event == "brake"]
    assert len(sensor) == 1 and sensor.t.iloc[0] == s["t_detect"]
    assert len(brake) == 1 and brake.t.iloc[0] == s["t_brake"]
    assert brake.t.iloc[0] == pytest.approx(s["t_detect"] + 0.070, rel=1e-12)
    begins = ev[ev.event == "object_contact_begin"]
    assert (begins.direction == "begin").all() and len(begins) == s["object_impacts"]
    assert (ev[ev.event == "sensor"].direction == "").all()
    # the state at the sensor event: the stroke is the sensor threshold (1.5 mm)
    assert sensor.s.iloc[0] == pytest.approx(1.5e-3, rel=1e-9)


def test_a_numerical_failure_is_a_status_not_an_exception(cli_json):
    run = cushion.simulate(set={"solver.max_steps": 10})
    assert run.status == "max_steps" and run.summary["message"]
    assert same(run.summary, cli_json("--set", "solver.max_steps=10"))


def test_defaults_keys_and_load_scene():
    keys = cushion.keys()
    assert list(keys.columns) == ["key", "default", "unit", "description"]
    for module in ("hydraulic", "bistable", "rigid"):
        d = cushion.defaults(module)
        assert d["module"] == module
        assert list(d) == list(keys.key)
    d = cushion.defaults()
    # the paper's Table 1 values and the defaults (docs/model.md, "Parameters and defaults")
    assert d["robot.dead_time"] == 0.070 and d["hydraulic.gas_pressure"] == 1000.0
    assert d["object.mass"] == 0.246 and d["solver.method"] == "auto"
    assert dict(zip(keys.key, keys.default)) == d
    assert keys.set_index("key").loc["robot.dead_time", "unit"] == "s"
    assert keys.set_index("key").loc["hydraulic.gas_pressure", "unit"] == "Pa"
    scene = cushion.load_scene(ROOT / "sweeps/scenes/paper-bistable-dt10.toml")
    assert scene["module"] == "bistable" and scene["robot.dead_time"] == 0.010
    # a scene dict round-trips through simulate
    assert same(cushion.simulate(scene).summary, cushion.simulate(ROOT / "sweeps/scenes/paper-bistable-dt10.toml").summary)


def test_a_prepared_scene_runs_as_its_file_and_overrides(cli_json):
    path = ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"
    scene = cushion.Scene(path, set={"module": "bistable", "robot.dead_time": 0.01})
    want = cli_json(path, "--set", "module=bistable", "--set", "robot.dead_time=0.01",
                    "--set", "solver.rtol=1e-8")
    # reused: each run starts from a copy, and the shorthands do not change the scene
    for _ in range(2):
        assert same(cushion.simulate(scene, rtol=1e-8).summary, want)
    assert scene.to_dict()["solver.rtol"] == 1e-6
    assert same(cushion.simulate(scene, set={"solver.rtol": 1e-8}).summary, want)
    # its keys are the file's with the overrides
    expected = cushion.load_scene(path)
    expected.update({"module": "bistable", "robot.dead_time": 0.01})
    assert scene.to_dict() == expected
    assert "module='bistable'" in repr(scene) and "dead_time=0.01 s" in repr(scene)
    # pickled as its keys (for another process), the same runs
    again = pickle.loads(pickle.dumps(scene))
    assert again.to_dict() == expected
    assert same(cushion.simulate(again, rtol=1e-8).summary, want)


def test_a_prepared_scene_is_checked_when_made():
    with pytest.raises(cushion.ConfigError, match=r"robot.dead_time.*-1.*>= 0"):
        cushion.Scene(set={"robot.dead_time": -1.0})
    with pytest.raises(cushion.ConfigError, match="scene = 3: expected .*cushion.Scene"):
        cushion.Scene(3)
    with pytest.raises(cushion.ConfigError, match="scene = 3: expected .*cushion.Scene"):
        cushion.simulate(3)


def test_two_threads_simulate_at_once():
    from concurrent.futures import ThreadPoolExecutor

    scenes = [{"robot.dead_time": dt} for dt in np.linspace(0.0, 0.1, 12)]
    alone = [cushion.simulate(set=s, trajectory=False).summary for s in scenes]
    with ThreadPoolExecutor(2) as pool:
        together = list(pool.map(lambda s: cushion.simulate(set=s, trajectory=False).summary, scenes))
    assert all(same(a, b) for a, b in zip(alone, together))


def test_the_implicit_method_from_python_equals_the_command_line(cli_json):
    run = cushion.simulate(ROOT / "sweeps/scenes/paper-bistable-dt10.toml", method="rodas", trajectory=False)
    assert same(run.summary, cli_json(ROOT / "sweeps/scenes/paper-bistable-dt10.toml", "--set", "solver.method=rodas"))
    assert run.status == "ok"


def test_auto_solves_the_compressible_liquid_and_logs_its_switch(cli_json):
    scene = ROOT / "sweeps/scenes/paper-hydraulic-dt70.toml"
    liquid = {"hydraulic.bulk_modulus": 1.5e9}
    run = cushion.simulate(scene, set=liquid, method="auto")
    assert same(run.summary, cli_json(scene, "--set", "hydraulic.bulk_modulus=1.5e9", "--set", "solver.method=auto"))
    assert run.status == "ok"
    assert run.stats["method_switches"] >= 1 and run.stats["jacobians"] > 0
    switches = run.events[run.events["event"] == "switch_to_rodas"]
    assert len(switches) == run.stats["method_switches"]
    # the lumped model's peak force is within 2e-4 of the compressible one's (docs/model.md)
    lumped = cushion.simulate(scene, trajectory=False)
    assert abs(run.summary["peak_robot_force"] / lumped.summary["peak_robot_force"] - 1) < 2e-4


def test_the_default_method_finishes_the_compressible_liquid():
    run = cushion.simulate(set={"hydraulic.bulk_modulus": 1.5e9}, trajectory=False)
    assert run.summary["status"] == "ok"
    assert run.summary["stats"]["method_switches"] >= 1
    # dp5 alone is held at its stability limit there
    dp5 = cushion.simulate(
        set={"hydraulic.bulk_modulus": 1.5e9, "solver.max_steps": 20000}, method="dp5", trajectory=False
    )
    assert dp5.summary["status"] == "max_steps"
