#!/usr/bin/env bash
# The Python environment of the benchmark scripts in lab/: .venv/ at the top (the one
# scripts/test.sh uses), with lab/requirements.txt (SciPy, pandas, matplotlib, the compiled
# peer's numba and CyRK, maturin) and the `cushion` package built from this checkout by maturin.
# Idempotent; `--no-package` skips the build (the SciPy-only scripts do not import cushion).
#
#     bash lab/setup_venv.sh && .venv/bin/python -m lab.work_precision
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/venv.sh
venv_create
.venv/bin/python -m pip install -q -r lab/requirements.txt
if [ "${1:-}" != "--no-package" ]; then
    package_install "" --no-deps
fi
