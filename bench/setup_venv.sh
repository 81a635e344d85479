#!/usr/bin/env bash
# Python environment for the reference scripts in bench/ (SciPy comparisons): .venv/ at the top.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/pip install -q numpy scipy
