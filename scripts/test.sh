#!/usr/bin/env bash
# Every test of the project, on a fresh machine:
#   1. the Rust tests of the whole workspace (cargo fetches the crates it needs): unit,
#      integration and end-to-end tests (the `cushion` command run as a user runs it);
#   2. the profile-guided build of the command (scripts/build_pgo.sh), whose numbers must be the
#      plain build's to the bit (scripts/pgo/same_numbers.sh); skipped, and said so, where rustup
#      cannot add the compiler's llvm-tools;
#   3. the Python package: a virtual environment in .venv/, the wheel built by maturin and
#      installed with its test dependencies (numpy, pandas, pyarrow, matplotlib,
#      dask[distributed], pytest, mcap, nbformat), then pytest on tests/python/.
# Benchmarks are not run here (see docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."

cargo test --workspace --locked

pgo=0
bash scripts/build_pgo.sh || pgo=$?
case $pgo in
    0) bash scripts/pgo/same_numbers.sh target/pgo/release/cushion target/debug/cushion ;;
    3) echo "SKIPPED: the profile-guided build (no llvm-tools for this compiler)" >&2 ;;
    *) exit "$pgo" ;;
esac

source scripts/venv.sh
venv_create
package_install "[test]"

# The Python tests compare the package with the command built by `cargo test` above.
CUSHION_BIN="$PWD/target/debug/cushion" .venv/bin/python -m pytest tests/python -q
