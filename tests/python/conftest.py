"""Shared fixtures: the repository's paths and the `cushion` command, to compare the Python
package with what the command writes for the same input."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "sweeps" / "scenes").glob("paper-*.toml"))


def _find_cli() -> Path:
    """The `cushion` binary: $CUSHION_BIN (the test command sets it), else a built one in
    target/, else built now."""
    env = os.environ.get("CUSHION_BIN")
    if env:
        return Path(env)
    for profile in ("release", "ci", "debug"):
        p = ROOT / "target" / profile / "cushion"
        if p.exists():
            return p
    subprocess.run(["cargo", "build", "--bin", "cushion"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "cushion"


@pytest.fixture(scope="session")
def cli():
    """Run the command: `cli("simulate", "--json")` -> CompletedProcess (text)."""
    exe = _find_cli()
    assert exe.exists(), exe

    def run(*args: str | os.PathLike[str], check: bool = True, cwd: os.PathLike[str] | None = None):
        out = subprocess.run(
            [str(exe), *map(str, args)], capture_output=True, text=True, cwd=cwd or ROOT
        )
        if check and out.returncode != 0:
            raise AssertionError(f"cushion {' '.join(map(str, args))}: {out.returncode}\n{out.stderr}")
        return out

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    def run(*args: str | os.PathLike[str]) -> dict:
        out = cli("simulate", *args, "--json", check=False)
        # 0: the run ended ok; 1: it ended with another status, summary still printed
        assert out.returncode in (0, 1), out.stderr
        return json.loads(out.stdout)

    return run


def same(a, b) -> bool:
    """Equal to the bit: floats by value with NaN equal to NaN (JSON null stays None)."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (a != a and b != b)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


def copy_sweep(tmp: Path, name: str) -> Path:
    """A sweep file of sweeps/ copied into `tmp`, with the scenes it names beside it."""
    shutil.copytree(ROOT / "sweeps" / "scenes", tmp / "scenes", dirs_exist_ok=True)
    dst = tmp / name
    shutil.copy(ROOT / "sweeps" / name, dst)
    return dst


_INTERRUPTED = r"""
import sys, cushion
config, out = {config!r}, {out!r}
def progress(done, total):
    print(done, flush=True)
try:
    cushion.{call}(config, out=out, threads=1, progress=progress)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(3)
print("finished", flush=True)
"""


def interrupt(call: str, config, out: Path, after: int) -> tuple[int | None, str, str]:
    """Run `cushion.<call>(config, out=out, threads=1, progress=...)` in a child Python and
    press Ctrl-C (SIGINT) once it reports `after` runs done; its exit status (3 where the call
    raised KeyboardInterrupt), the rest of its output and its stderr."""
    import signal
    import sys

    child = subprocess.Popen(
        [sys.executable, "-c", _INTERRUPTED.format(call=call, config=config, out=str(out))],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    for line in child.stdout:
        if line.strip().isdigit() and int(line) >= after:
            child.send_signal(signal.SIGINT)
            break
    rest, err = child.communicate(timeout=120)
    return child.returncode, rest, err
