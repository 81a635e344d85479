"""Scene keys: their defaults, units and meanings, and scene files read into dicts."""

from __future__ import annotations

import os
from typing import Any

import pandas as pd

from . import _cushion


def defaults(module: str = "hydraulic") -> dict[str, Any]:
    """The default scene of ``module`` ("hydraulic", "bistable" or "rigid") as
    ``{"section.key": value}``, every key (SI units; see :func:`keys`)."""
    return _cushion.defaults(module)


def keys() -> pd.DataFrame:
    """Every scene key: columns ``key``, ``default`` (the hydraulic scene's), ``unit`` and
    ``description``, in the order of docs/scene-keys.md."""
    rows = _cushion.keys()
    frame = pd.DataFrame(rows, columns=["key", "default", "unit", "description"])
    frame["default"] = frame["default"].astype(object)
    return frame


def load_scene(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a scene file (TOML) into ``{"section.key": value}``, every key, the file's values
    over the defaults. A file that cannot be read raises :class:`FileNotFoundError` (or another
    :class:`OSError`); invalid TOML, unknown keys and wrong types :class:`cushion.ConfigError`."""
    return _cushion.load_scene(os.fspath(path))
