"""The ``cushion`` command line, installed with the package: the console script ``cushion`` and
``python -m cushion`` run the same compiled command as the ``cushion`` binary (its arguments,
messages and exit statuses: 0 success, 1 a run not ``ok`` or a failed write, 2 bad input)."""

from __future__ import annotations

import signal
import sys
from collections.abc import Sequence

from . import _cushion


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``cushion`` with ``argv`` (default: this process's arguments) and return its exit status.

    >>> from cushion._cli import main
    >>> main(["simulate", "--json"])   # prints the summary, returns 0
    """
    args = ["cushion", *(sys.argv[1:] if argv is None else argv)]
    sys.stdout.flush()
    sys.stderr.flush()
    if argv is not None:
        return _cushion.main(args)
    # As the console script, Ctrl-C ends the process as it ends the binary (Python's own
    # handler would only run once the compiled command returned).
    previous = signal.signal(signal.SIGINT, signal.SIG_DFL)
    try:
        return _cushion.main(args)
    finally:
        signal.signal(signal.SIGINT, previous)
