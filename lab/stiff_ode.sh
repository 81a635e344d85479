#!/usr/bin/env bash
# The implicit method (rodas) on the classic stiff problems: work (steps, evaluations of f,
# Jacobians, LU factorizations), accuracy against the published reference, wall time; DOPRI5
# beside it where it finishes. Then SciPy's Radau and BDF on the same problems, if the
# Python environment of lab/setup_venv.sh is there.
#   bash lab/stiff_ode.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release -q -p cushion-studies --bin stiff_ode
if [ -x .venv/bin/python ] && .venv/bin/python -c 'import scipy' 2>/dev/null; then
    echo
    .venv/bin/python -m lab.stiff_scipy
fi
