#!/usr/bin/env bash
# Every test of the project, on a fresh machine:
#   1. the Rust tests of the whole workspace (cargo fetches the crates it needs): unit,
#      integration and end-to-end tests (the `cushion` command run as a user runs it);
#   2. the Python package: a virtual environment in .venv/, the wheel built by maturin and
#      installed with its test dependencies (numpy, pandas, pyarrow, matplotlib,
#      dask[distributed], pytest, mcap, nbformat), then pytest on tests/python/.
# Benchmarks are not run here (see docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."

cargo test --workspace --locked

source scripts/venv.sh
venv_create
package_install "[test]"

# The Python tests compare the package with the command built by `cargo test` above.
CUSHION_BIN="$PWD/target/debug/cushion" .venv/bin/python -m pytest tests/python -q
