"""The type stubs of the compiled module match it: every function's parameters, their names,
kinds and defaults, and the module's names (mypy's stubtest, as typeshed checks its stubs)."""

from __future__ import annotations

import subprocess
import sys

import pytest

pytest.importorskip("mypy")


def test_the_compiled_modules_stubs_match_it():
    out = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "cushion._cushion"],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stdout + out.stderr
