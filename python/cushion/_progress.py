"""The progress bar of a sweep: tqdm in a terminal or a notebook, or the caller's callback."""

from __future__ import annotations

import sys
from typing import Callable

Progress = Callable[[int, int], None]


def _in_notebook() -> bool:
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    try:
        ip = shell.get_ipython()  # type: ignore[attr-defined]
    except Exception:
        return False
    return ip is not None and type(ip).__name__ == "ZMQInteractiveShell"


class _Bar:
    """A tqdm bar fed with (done, total) counts; closed when the sweep ends."""

    def __init__(self, desc: str) -> None:
        from tqdm.auto import tqdm

        self._bar = tqdm(total=None, unit="run", desc=desc, dynamic_ncols=True)

    def __call__(self, done: int, total: int) -> None:
        if self._bar.total != total:
            self._bar.total = total
        self._bar.n = done
        self._bar.refresh()

    def close(self) -> None:
        self._bar.close()


def progress_for(progress: bool | Progress | None, desc: str) -> tuple[Progress | None, Callable[[], None]]:
    """The callback to hand to the engine, and what to call when it ends.

    ``None``: a bar when standard error is a terminal or the code runs in a notebook;
    ``True``: always a bar; ``False``: none; a callable: called as ``progress(done, total)``.
    """
    if callable(progress) and not isinstance(progress, bool):
        return progress, lambda: None
    show = progress if progress is not None else (_in_notebook() or _stderr_is_terminal())
    if not show:
        return None, lambda: None
    bar = _Bar(desc)
    return bar, bar.close


def _stderr_is_terminal() -> bool:
    try:
        return sys.stderr is not None and sys.stderr.isatty()
    except Exception:
        return False


