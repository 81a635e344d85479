#!/usr/bin/env bash
# The Python environment of the benchmark scripts in bench/: .venv/ at the top (the one
# scripts/test.sh uses), with bench/requirements.txt (SciPy, pandas, matplotlib, the compiled
# peer's numba and CyRK, maturin) and the `cushion` package built from this checkout by maturin.
# Idempotent; `--no-package` skips the build (the SciPy-only scripts do not import cushion).
#
#     bash bench/setup_venv.sh && .venv/bin/python bench/work_precision.py
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-python3}
[ -x .venv/bin/python ] || "$python" -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -r bench/requirements.txt
if [ "${1:-}" != "--no-package" ]; then
    out=$(mktemp -d)
    .venv/bin/maturin build --release --locked --out "$out"
    .venv/bin/python -m pip install -q --force-reinstall --no-deps "$out"/cushion-*.whl
    rm -rf "$out"
fi
