#!/usr/bin/env bash
# Wall time per run of each paper scene (rtol 1e-6), in-process: `loop_scene N SCENE` for the
# five scenes in turn, ROUNDS times, and the fastest and the median round of each. This VM's
# speed moves by a third within minutes, so a single timing says little; interleaving the
# scenes shares the slow and fast minutes out, and the fastest round is the one least
# disturbed. Instruction counts, which repeat, are `lab/instructions.sh`.
#   bash lab/wall_time.sh [ROUNDS] [N]       # defaults 15 and 300 (about a minute)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-15}
n=${2:-300}
cargo build --release -q -p cushion-studies --bin loop_scene
bin=${CARGO_TARGET_DIR:-target}/release/loop_scene
scenes=(sweeps/scenes/paper-*.toml)
declare -A times
for _ in $(seq "$rounds"); do
    for s in "${scenes[@]}"; do
        times[$s]+=" $("$bin" "$n" "$s" | awk '{print $1}')"
    done
done
printf '%-24s %10s %10s\n' scene 'min µs' 'median µs'
for s in "${scenes[@]}"; do
    # shellcheck disable=SC2086
    printf '%-24s %10s %10s\n' "$(basename "$s" .toml)" \
        $(printf '%s\n' ${times[$s]} | sort -g | awk '{a[NR] = $1} END {print a[1], a[int((NR + 1) / 2)]}')
done
