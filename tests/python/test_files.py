"""A file the caller names that cannot be read raises Python's own OSError subclass (as `open`
would), from every public function that takes a path; a file that reads but is not a valid
scene or sweep stays a `cushion.ConfigError`."""

from __future__ import annotations

import errno

import pytest

import cushion
import cushion.dask as cdask
from conftest import ROOT

READERS = {
    "simulate": lambda p: cushion.simulate(p),
    "Scene": lambda p: cushion.Scene(p),
    "load_scene": lambda p: cushion.load_scene(p),
    "sweep": lambda p: cushion.sweep(p, progress=False),
    "read_mcap": lambda p: cushion.read_mcap(p),
    "dask.sweep_frame": lambda p: cdask.sweep_frame(p),
    "design": lambda p: cushion.design(p, progress=False),
    "sensitivity": lambda p: cushion.sensitivity(p, progress=False),
}


@pytest.mark.parametrize("name", READERS)
def test_a_missing_file_is_file_not_found(name, tmp_path):
    missing = tmp_path / "nofile.toml"
    with pytest.raises(FileNotFoundError) as e:
        READERS[name](missing)
    assert isinstance(e.value, OSError) and not isinstance(e.value, cushion.ConfigError)
    assert e.value.errno == errno.ENOENT
    assert e.value.filename == str(missing)
    assert "nofile.toml" in str(e.value)
    # a str path too
    with pytest.raises(FileNotFoundError):
        READERS[name](str(missing))


@pytest.mark.parametrize("name", ["simulate", "load_scene", "sweep", "read_mcap", "design", "sensitivity"])
def test_a_folder_is_is_a_directory(name, tmp_path):
    with pytest.raises(IsADirectoryError) as e:
        READERS[name](tmp_path)
    assert e.value.errno == errno.EISDIR


@pytest.mark.parametrize("name", ["simulate", "Scene", "load_scene", "sweep", "design", "sensitivity"])
def test_a_file_that_is_not_toml_stays_a_config_error(name, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("module = = 3\n")
    with pytest.raises(cushion.ConfigError, match="bad.toml"):
        READERS[name](bad)


def test_a_bad_key_in_a_file_stays_a_config_error(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[robot]\ndead_tim = 0.1\n")
    with pytest.raises(cushion.ConfigError, match="robot.dead_tim"):
        cushion.simulate(bad)


def test_a_file_that_is_not_mcap_is_an_os_error_not_a_missing_file(tmp_path):
    bad = tmp_path / "run.mcap"
    bad.write_bytes(b"not an mcap file")
    with pytest.raises(OSError) as e:
        cushion.read_mcap(bad)
    assert not isinstance(e.value, FileNotFoundError)


def test_a_sweeps_missing_scene_names_its_key(tmp_path):
    # the file named by the call exists; the scene it names is a bad value of its key `scene`
    sweep = tmp_path / "s.toml"
    sweep.write_text(
        'name = "s"\nscene = "no-such-scene.toml"\n[[axis]]\nkey = "robot.dead_time"\nvalues = [0.01]\n'
    )
    with pytest.raises(cushion.ConfigError, match="no-such-scene.toml"):
        cushion.sweep(sweep, progress=False)
