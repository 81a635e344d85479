"""The `cushion` command installed with the wheel (the console script and `python -m cushion`)
is the binary's command line: the same version, the same output, the same exit statuses."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cushion
from conftest import ROOT, SCENES

# the console script pip installed beside this interpreter
SCRIPT = Path(sys.executable).with_name("cushion")


def installed(*args: str, module: bool = False) -> subprocess.CompletedProcess:
    argv = [sys.executable, "-m", "cushion", *args] if module else [str(SCRIPT), *args]
    return subprocess.run(argv, capture_output=True, text=True, cwd=ROOT)


def test_the_wheel_installs_the_command():
    assert SCRIPT.exists(), f"no console script at {SCRIPT}"
    assert os.access(SCRIPT, os.X_OK)


@pytest.mark.parametrize("module", [False, True])
def test_version_names_the_package_version(cli, module):
    out = installed("--version", module=module)
    assert out.returncode == 0, out.stderr
    line = out.stdout.strip()
    assert line.startswith(f"cushion {cushion.__version__}"), line
    # where both were built from a git checkout, the line names its commit
    if "(commit " in line:
        commit = line.split("(commit ")[1].rstrip(")")
        assert len(commit) == 40 and all(c in "0123456789abcdef" for c in commit), line


@pytest.mark.parametrize("module", [False, True])
def test_simulate_json_equals_the_binarys(cli, module):
    scene = SCENES[0]
    args = ("simulate", str(scene), "--set", "robot.dead_time=0.03", "--json")
    ours = installed(*args, module=module)
    theirs = cli(*args, check=False)
    assert ours.returncode == theirs.returncode == 0, ours.stderr
    assert ours.stdout == theirs.stdout
    assert json.loads(ours.stdout)["status"] == "ok"


@pytest.mark.parametrize("module", [False, True])
def test_bad_input_exits_2_with_the_binarys_message(cli, module):
    args = ("simulate", "--set", "robot.dead_tim=0.1")
    ours = installed(*args, module=module)
    theirs = cli(*args, check=False)
    assert ours.returncode == theirs.returncode == 2
    assert ours.stderr == theirs.stderr
    assert "robot.dead_tim" in ours.stderr
    # a usage error is clap's, also status 2
    ours = installed("simulat", module=module)
    assert ours.returncode == 2 and "simulat" in ours.stderr


def test_a_run_that_is_not_ok_exits_1(cli):
    args = ("simulate", "--set", "solver.max_steps=10")
    ours = installed(*args)
    assert ours.returncode == cli(*args, check=False).returncode == 1
    assert "max_steps" in ours.stdout


def test_sweep_from_the_console_script_writes_the_binarys_summary(cli, tmp_path):
    sweep = ROOT / "sweeps" / "paper.toml"
    ours = installed("sweep", str(sweep), "--out", str(tmp_path / "a"), "--threads", "2", "--quiet")
    assert ours.returncode == 0, ours.stderr
    cli("sweep", sweep, "--out", tmp_path / "b", "--threads", "1", "--quiet")
    a = (tmp_path / "a" / "summary.csv").read_bytes()
    assert a == (tmp_path / "b" / "summary.csv").read_bytes()


@pytest.mark.parametrize("shell, marker", [("bash", "complete -F"), ("zsh", "#compdef cushion"), ("fish", "complete -c cushion")])
def test_completions(cli, shell, marker):
    out = installed("completions", shell)
    assert out.returncode == 0, out.stderr
    assert marker in out.stdout
    # every subcommand is offered
    for sub in ("simulate", "sweep", "merge", "design", "sensitivity", "completions"):
        assert sub in out.stdout
    assert out.stdout == cli("completions", shell).stdout
    assert installed("completions", "tcsh").returncode == 2


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
def test_bash_completion_offers_the_subcommands(cli, tmp_path):
    script = tmp_path / "cushion.bash"
    script.write_text(cli("completions", "bash").stdout)
    probe = (
        f"source {script}; COMP_WORDS=(cushion s); COMP_CWORD=1; COMP_LINE='cushion s'; "
        "COMP_POINT=${#COMP_LINE}; _cushion cushion s cushion; printf '%s\\n' \"${COMPREPLY[@]}\""
    )
    out = subprocess.run(["bash", "-c", probe], capture_output=True, text=True)
    assert set(out.stdout.split()) == {"simulate", "sweep", "sensitivity"}, out.stdout + out.stderr


def test_main_returns_the_status_without_exiting():
    from cushion._cli import main

    assert main(["simulate", "--set", "robot.dead_tim=1"]) == 2
    assert main(["--version"]) == 0


def test_the_wheel_carries_both_licenses():
    from importlib.metadata import files

    names = {p.name for p in files("cushion") or []}
    assert {"LICENSE-MIT", "LICENSE-APACHE"} <= names, names
