#!/usr/bin/env bash
# Every test of the project, on a fresh machine:
#   1. the Rust tests of the whole workspace (cargo fetches the crates it needs): unit,
#      integration and end-to-end tests (the `cushion` command run as a user runs it);
#   2. the Python package: a virtual environment in .venv/ with the test dependencies (numpy,
#      pandas, pyarrow, matplotlib, dask[distributed], pytest, mcap, nbformat, mypy for the
#      stubs, SALib; installed while step 1 compiles), the wheel built by maturin and installed
#      into it, then pytest on tests/python/
# Both use one build, the `ci` profile of Cargo.toml (optimised, no link-time optimisation): the
# wheel reuses the crates the Rust tests compiled. The profile-guided build's bit-equality with
# the plain build is checked by scripts/check_pgo.sh; benchmarks are not run here
# (docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/venv.sh

# The virtual environment and the Python test dependencies install while cargo compiles:
# downloading and unpacking wheels wants little of the two cores the Rust build keeps busy.
venv_log=$(mktemp)
(venv_create && dependencies_install test && .venv/bin/python -m pip install -q "maturin>=1.5,<2") \
    >"$venv_log" 2>&1 &
venv_job=$!

rust_status=0
cargo test --workspace --locked --profile ci || rust_status=$?
venv_status=0
wait "$venv_job" || venv_status=$?
if [ "$venv_status" -ne 0 ]; then
    echo "scripts/test.sh: the Python environment could not be made:" >&2
    cat "$venv_log" >&2
fi
rm -f "$venv_log"
[ "$rust_status" -eq 0 ] || exit "$rust_status"
[ "$venv_status" -eq 0 ] || exit "$venv_status"

CUSHION_WHEEL_PROFILE=ci package_install "[test]"

# The Python tests compare the package with the command built by `cargo test` above.
CUSHION_BIN="$PWD/target/ci/cushion" .venv/bin/python -m pytest tests/python -q
