#!/usr/bin/env bash
# The profile-guided build (scripts/build_pgo.sh) gives the plain build's numbers to the bit:
# builds both commands and compares their outputs (scripts/pgo/same_numbers.sh). Run it after a
# change to the build settings, the training runs or the compiler; it takes about as long as two
# release builds and the test build. Exit status 3 where rustup cannot add the compiler's
# llvm-tools (nothing checked).
#   bash scripts/check_pgo.sh
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/build_pgo.sh
cargo build --locked --profile ci --bin cushion
bash scripts/pgo/same_numbers.sh target/pgo/release/cushion target/ci/cushion
