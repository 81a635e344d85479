#!/usr/bin/env bash
# Instructions per run of each paper scene (rtol 1e-6), counted by valgrind's cachegrind:
# they repeat to within a few instructions per run whatever else the machine does, unlike
# wall time on this VM.
#   bash lab/instructions.sh            # needs valgrind (Debian package)
# Per run = (count for 200 runs - count for 0 runs) / 200, so start-up and parsing drop out.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p cushion-studies --bin loop_scene
bin=${CARGO_TARGET_DIR:-target}/release/loop_scene
count() {
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null "$@" 2>&1 \
        | sed -n 's/.*I *refs: *//p' | tr -d ','
}
printf '%-24s %14s\n' scene instructions/run
for scene in sweeps/scenes/paper-*.toml; do
    zero=$(count "$bin" 0 "$scene")
    many=$(count "$bin" 200 "$scene")
    printf '%-24s %14d\n' "$(basename "$scene" .toml)" $(((many - zero) / 200))
done
