"""Every kind of bad argument raises `cushion.ConfigError` (a ValueError) with the command
line's message, naming the key and the value; nothing is written; a panic is a RuntimeError."""

from __future__ import annotations

import pytest

import cushion
from cushion import _cushion
from conftest import ROOT


def cli_message(cli, *args):
    out = cli("simulate", *args, check=False)
    assert out.returncode == 2, out.stderr
    return out.stderr.strip().removeprefix("cushion simulate: ")


@pytest.mark.parametrize(
    "set_, cli_args, key",
    [
        ({"robot.dead_tim": 0.1}, ["--set", "robot.dead_tim=0.1"], "robot.dead_tim"),
        ({"object.mass": "heavy"}, ["--set", "object.mass=\"heavy\""], "object.mass"),
        ({"object.mass": -1.0}, ["--set", "object.mass=-1.0"], "object.mass"),
        ({"object.mass": float("nan")}, ["--set", "object.mass=nan"], "object.mass"),
        ({"module": "pneumatic"}, ["--set", "module=pneumatic"], "module"),
        ({"solver.method": "rk45"}, ["--set", "solver.method=rk45"], "solver.method"),
        ({"hydraulic.orifice_radius": 0.05}, ["--set", "hydraulic.orifice_radius=0.05"], "hydraulic.orifice_radius"),
        ({"tool.sensor_threshold": 1.0}, ["--set", "tool.sensor_threshold=1.0"], "tool.sensor_threshold"),
        ({"energy.ledger": 3}, ["--set", "energy.ledger=3"], "energy.ledger"),
    ],
)
def test_bad_keys_and_values_carry_the_command_lines_message(cli, set_, cli_args, key):
    with pytest.raises(cushion.ConfigError) as e:
        cushion.simulate(set=set_)
    assert isinstance(e.value, ValueError)
    assert key in str(e.value)
    # the command says which --set it refuses, then the same message
    message = cli_message(cli, *cli_args)
    assert message in (str(e.value), f"--set {cli_args[1]}: {e.value}")


def test_bad_shorthands_and_arguments_name_what_to_fix():
    for kwargs, needle in [
        ({"rtol": -1.0}, "solver.rtol"),
        ({"atol": 0.0}, "solver.atol"),
        ({"method": "radau5"}, "solver.method"),
        ({"sample_interval": -1.0}, "sample_interval"),
        ({"sample_interval": float("inf")}, "sample_interval"),
        ({"set": {1: 2}}, "section.key"),
        ({"set": {"robot.dead_time": object()}}, "robot.dead_time"),
        ({"set": {"robot.dead_time": [0.1]}}, "robot.dead_time"),
    ]:
        with pytest.raises(cushion.ConfigError, match=needle.replace(".", r"\.")):
            cushion.simulate(**kwargs)


def test_bad_scenes(cli, tmp_path):
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        cushion.simulate(missing)
    with pytest.raises(cushion.ConfigError, match="scene"):
        cushion.simulate(42)
    with pytest.raises(cushion.ConfigError, match="robot.speed"):
        cushion.simulate({"robot": {"speed": 1.0}})
    with pytest.raises(cushion.ConfigError, match="gearbox"):
        cushion.simulate({"gearbox": {"ratio": 3}})
    bad = tmp_path / "bad.toml"
    bad.write_text("module = \n")
    with pytest.raises(cushion.ConfigError) as e:
        cushion.simulate(bad)
    assert str(e.value) == cli_message(cli, bad)
    with pytest.raises(cushion.ConfigError, match="module"):
        cushion.defaults("pneumatic")
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        cushion.load_scene(missing)


def test_bad_sweeps_raise_before_anything_is_written(tmp_path):
    out = tmp_path / "out"
    good_axis = {"key": "robot.dead_time", "values": [0.01, 0.07]}
    for config, needle in [
        ({"axis": [{"key": "robot.dead_tim", "values": [0.1]}]}, "robot.dead_tim"),
        ({"axis": [{"key": "object.mass", "values": [0.1, -1.0]}]}, "object.mass"),
        ({"sampling": {"mode": "random"}, "axis": [good_axis]}, "random"),
        ({"axis": [{"key": "robot.dead_time", "linspace": [0.0, 0.1]}]}, "linspace"),
        ({"scene": "no-such-scene.toml", "axis": [good_axis]}, "no-such-scene.toml"),
        ({"set": {"tool.mass": "x"}, "axis": [good_axis]}, "tool.mass"),
        (3.5, "config"),
    ]:
        with pytest.raises(cushion.ConfigError, match=needle.replace(".", r"\.")):
            cushion.sweep(config, out=out, progress=False)
        assert not out.exists(), config
    with pytest.raises(cushion.ConfigError, match="resume"):
        cushion.sweep({"axis": [good_axis]}, resume=True, progress=False)
    with pytest.raises(cushion.ConfigError, match="threads"):
        cushion.sweep({"axis": [good_axis]}, threads=0, progress=False)


def test_read_mcap_of_a_missing_file_or_run(tmp_path, cli):
    with pytest.raises(OSError):
        cushion.read_mcap(tmp_path / "none.mcap")
    (tmp_path / "junk.mcap").write_bytes(b"not an mcap file")
    with pytest.raises(OSError, match="junk.mcap"):
        cushion.read_mcap(tmp_path / "junk.mcap")
    cli("simulate", "--mcap", tmp_path / "one.mcap")
    with pytest.raises(cushion.ConfigError, match="run"):
        cushion.read_mcap(tmp_path / "one.mcap", run=5)


def test_a_panic_becomes_a_runtime_error_not_an_abort(capfd):
    with pytest.raises(RuntimeError, match="deliberate panic"):
        _cushion._panic_guard_check()
    # and the interpreter lives on, quietly
    assert cushion.simulate(trajectory=False).status == "ok"
    assert "panicked" not in capfd.readouterr().err
