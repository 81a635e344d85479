#!/usr/bin/env bash
# Every test of the project, on a fresh machine:
#   1. the Rust tests of the whole workspace (cargo fetches the crates it needs): unit,
#      integration and end-to-end tests (the `cushion` command run as a user runs it);
#   2. the Python package: a virtual environment in .venv/, the wheel built by maturin and
#      installed with its test dependencies (numpy, pandas, pyarrow, matplotlib,
#      dask[distributed], pytest, mcap, nbformat, mypy for the stubs), then pytest on tests/python/
# Both use one build, the `ci` profile of Cargo.toml (optimised, no link-time optimisation): the
# wheel reuses the crates the Rust tests compiled. The profile-guided build's bit-equality with
# the plain build is checked by scripts/check_pgo.sh; benchmarks are not run here
# (docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."

cargo test --workspace --locked --profile ci

source scripts/venv.sh
venv_create
CUSHION_WHEEL_PROFILE=ci package_install "[test]"

# The Python tests compare the package with the command built by `cargo test` above.
CUSHION_BIN="$PWD/target/ci/cushion" .venv/bin/python -m pytest tests/python -q
