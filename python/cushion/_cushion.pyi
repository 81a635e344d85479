# Type stubs of the compiled module cushion._cushion (crates/cushion-py). Users call the
# wrappers in cushion/__init__.py; these are the raw functions under them.
import os
from typing import Any, Callable, final

import numpy as np
import numpy.typing as npt

__version__: str
# the trajectory's columns, in the order of its rows: t, x_r, v_r, x_t, v_t, x_p, v_p, s, p1, F_c, F_r
COLUMNS: tuple[str, ...]
# figure 3's panels, top to bottom: dicts of title, quantity, symbol, unit, factor (from SI),
# curves (dicts of column, name, symbol, color) and absent (the note when nothing is drawn)
FIGURE3: tuple[dict[str, Any], ...]
# figure 3's dashed event lines: dicts of field (of the summary), label and color
FIGURE3_MARKS: tuple[dict[str, Any], ...]
# how the charts show each summary metric and scene key: dicts of key, kind ("metric" or
# "axis"), name, unit and factor (from SI)
QUANTITIES: tuple[dict[str, Any], ...]
__all__ = [
    "ConfigError",
    "__version__",
    "COLUMNS",
    "FIGURE3",
    "FIGURE3_MARKS",
    "QUANTITIES",
    "Scene",
    "DesignAnswer",
    "defaults",
    "keys",
    "load_scene",
    "simulate",
    "sweep",
    "design",
    "sensitivity",
    "resolve_sweep",
    "sweep_runs",
    "read_mcap",
    "recorded_runs",
    "main",
    "_panic_guard_check",
]

class ConfigError(ValueError):
    """Bad input: the message names the key, the value and what is allowed."""

# the trajectory: an (11, n) array, one row per column t, x_r, v_r, x_t, v_t, x_p, v_p, s, p1, F_c, F_r
_Columns = npt.NDArray[np.float64]
# the event log: times, names, and the state at each event as an (n, 11) array
_Events = tuple[npt.NDArray[np.float64], list[str], npt.NDArray[np.float64]]

@final
class Scene:
    """A scene read and checked once, to run many times (see cushion.simulate)."""

    def __new__(cls, scene: str | os.PathLike[str] | dict[str, Any] | None = None, set: dict[str, Any] | None = None) -> Scene: ...
    def to_dict(self) -> dict[str, Any]: ...
    def __reduce__(self) -> tuple[type[Scene], tuple[dict[str, Any]]]: ...

def defaults(module: str = "hydraulic") -> dict[str, Any]: ...
def keys() -> list[tuple[str, Any, str, str]]: ...
def load_scene(path: str) -> dict[str, Any]: ...
def simulate(
    scene: str | dict[str, Any] | Scene | None = None,
    set: dict[str, Any] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    trajectory: bool = True,
    sample_interval: float | None = None,
) -> tuple[dict[str, Any], _Columns | None, _Events]: ...
def sweep(
    config: str | dict[str, Any],
    threads: int | None = None,
    out: str | None = None,
    resume: bool = False,
    progress: Callable[[int, int], None] | None = None,
    git_commit: str | None = None,
) -> bytes:
    """The summary rows as an Arrow IPC stream."""

@final
class DesignAnswer:
    """An answered design question (cushion.Design wraps it)."""

    @property
    def design_keys(self) -> list[str]: ...
    @property
    def out_dir(self) -> str | None: ...
    def points(self) -> bytes:
        """One row per design point (design.parquet's columns), as an Arrow IPC stream."""
    def runs(self) -> bytes:
        """Every run made (runs.parquet's columns), as an Arrow IPC stream."""
    def answer(self) -> str:
        """The text of answer.json."""
    def map_margin(self, points: list[list[Any]]) -> list[float]: ...

def design(
    config: str | dict[str, Any],
    threads: int | None = None,
    out: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    git_commit: str | None = None,
) -> DesignAnswer: ...
def sensitivity(
    config: str | dict[str, Any],
    outputs: list[str] | None = None,
    threads: int | None = None,
    out: str | None = None,
    resume: bool = False,
    progress: Callable[[int, int], None] | None = None,
    git_commit: str | None = None,
) -> bytes:
    """The long table of Sobol indices (sensitivity.parquet's columns) as an Arrow IPC stream."""

def resolve_sweep(config: str | dict[str, Any]) -> tuple[str, int]:
    """The sweep as self-contained TOML text, and its run count."""

def sweep_runs(text: str, start: int, stop: int, threads: int | None = None) -> bytes:
    """Runs start..stop of a resolved sweep, as an Arrow IPC stream."""

def read_mcap(path: str, run: int | None = None) -> tuple[_Columns, _Events]: ...
def recorded_runs(path: str) -> list[int]: ...
def main(argv: list[str]) -> int:
    """Run the ``cushion`` command line with ``argv`` (program name first); its exit status."""

def _panic_guard_check() -> None: ...
