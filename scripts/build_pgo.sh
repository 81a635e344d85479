#!/usr/bin/env bash
# A profile-guided build (PGO) of the `cushion` command and, with --wheel, of the Python
# package. The compiler lays out the hot path (the step loop, the right-hand side, the event
# scan, the observers) from the branch and call counts of real runs: a run takes 10-13 % less
# time (docs/performance.md, "The profile-guided build"). The numbers are the same to the bit:
# PGO moves code and chooses what to inline, never which floating-point operations run
# (scripts/pgo/same_numbers.sh compares the two builds; scripts/check_pgo.sh runs both).
#
#   bash scripts/build_pgo.sh            # -> target/pgo/release/cushion
#   bash scripts/build_pgo.sh --wheel    # also the Python package, built into .venv/
#
# The steps, as rustc's and pydantic-core's own PGO builds take them:
#   1. an instrumented build (-Cprofile-generate) into target/pgo-gen/;
#   2. the training runs (scripts/pgo/train.sh): sweeps/design-space.toml, the engine's
#      defaults, and scripts/pgo/training.toml, every method over tolerances and
#      end-stop stiffnesses; with --wheel, the same runs through the instrumented package;
#   3. the counts merged by llvm-profdata, the one of the compiler's own LLVM (rustup's
#      `llvm-tools`, added if missing);
#   4. the build with the merged profile (-Cprofile-use) into target/pgo/ (the wheel: into
#      .venv/, as scripts/venv.sh builds the plain one).
# Two release builds of the workspace (with --wheel, four): several minutes. Needs rustup; exits
# with status 3, having built nothing, where rustup cannot add `llvm-tools`.
set -euo pipefail
cd "$(dirname "$0")/.."

wheel=false
case "${1:-}" in
    "") ;;
    --wheel) wheel=true ;;
    *) echo "usage: bash scripts/build_pgo.sh [--wheel]" >&2; exit 2 ;;
esac

# llvm-profdata must read the counts the compiler's LLVM writes: take rustup's, not the system's.
sysroot=$(rustc --print sysroot)
host=$(rustc -vV | sed -n 's/^host: //p')
profdata="$sysroot/lib/rustlib/$host/bin/llvm-profdata"
if [ ! -x "$profdata" ] && ! rustup component add llvm-tools --toolchain "$(basename "$sysroot")"; then
    echo "build_pgo.sh: no llvm-profdata for this compiler ($profdata): rustup could not add" \
        "the llvm-tools component; nothing was built" >&2
    exit 3
fi

root=$PWD
counts="$root/target/pgo-counts"
merged="$root/target/pgo.profdata"
rm -rf "$counts" "$merged"

# 1-2: the command, instrumented, and its training runs
RUSTFLAGS="-Cprofile-generate=$counts" \
    cargo build --release --locked --bin cushion --target-dir target/pgo-gen
bash scripts/pgo/train.sh target/pgo-gen/release/cushion

if $wheel; then
    # the package compiles the engine into another library, whose functions the command's
    # counts do not name: it is trained through Python on the same runs
    source scripts/venv.sh
    venv_create
    CARGO_TARGET_DIR=target/pgo-gen RUSTFLAGS="-Cprofile-generate=$counts" package_install ""
    .venv/bin/python scripts/pgo/train.py
fi

# 3: the counts of every process, merged
"$profdata" merge -o "$merged" "$counts"

# 4: the builds with the profile
RUSTFLAGS="-Cprofile-use=$merged" \
    cargo build --release --locked --bin cushion --target-dir target/pgo
if $wheel; then
    CARGO_TARGET_DIR=target/pgo RUSTFLAGS="-Cprofile-use=$merged" package_install ""
fi
echo "profile-guided build: target/pgo/release/cushion$($wheel && echo ', and the package in .venv/')"
