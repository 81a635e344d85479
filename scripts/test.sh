#!/usr/bin/env bash
# Every test of the project, on a fresh machine: fetches the Rust crates it needs and runs the
# unit, integration and end-to-end tests of the whole workspace (the `cushion` command is run
# as a user runs it). Benchmarks are not run here (see README).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --locked
