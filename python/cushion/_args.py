"""Arguments as the compiled engine takes them."""

from __future__ import annotations

import os
from typing import Any, Mapping

from . import _cushion


def path_or_dict(value: Any, name: str, expected: str) -> str | dict[str, Any]:
    """A path (``str`` or ``os.PathLike``) as a string, a mapping as a plain dict; anything
    else is a :class:`cushion.ConfigError` naming the argument and what it takes."""
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    if isinstance(value, Mapping):
        return dict(value)
    raise _cushion.ConfigError(f"{name} = {value!r}: expected {expected}")
