"""``python -m cushion ...``: the ``cushion`` command line (see :mod:`cushion._cli`)."""

import sys

from ._cli import main

sys.exit(main())
