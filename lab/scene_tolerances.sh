#!/usr/bin/env bash
# Cost against accuracy of the paper scenes, one row per tolerance: rtol 1e-3 .. 1e-10 with
# atol = rtol / 1000 (the scenes' own ratio), against the same scene at rtol 1e-12.
#   bash lab/scene_tolerances.sh [SCENE.toml]...     # needs valgrind (Debian package)
# Columns: steps and rhs evaluations; instructions per run (valgrind, (50 runs - 0 runs) / 50);
# the best wall time per run over 5 batches; then the absolute or relative (rel) errors of the
# detection time (s), the peak robot force (rel), the robot impulse (N s), the object's final
# speed (m/s) and the largest stroke (m); the energy ledger's residual; and whether the counts
# of object and end-stop impacts equal the reference's.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p cushion-studies --bin tolerance_row --bin loop_scene
row=${CARGO_TARGET_DIR:-target}/release/tolerance_row
loop=${CARGO_TARGET_DIR:-target}/release/loop_scene
count() {
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null "$@" 2>&1 \
        | sed -n 's/.*I *refs: *//p' | tr -d ','
}
scenes=("$@")
if [ ${#scenes[@]} -eq 0 ]; then
    scenes=(sweeps/scenes/paper-hydraulic-dt70.toml sweeps/scenes/paper-bistable-dt70.toml
        sweeps/scenes/paper-rigid.toml)
fi
for scene in "${scenes[@]}"; do
    echo
    echo "$(basename "$scene" .toml)"
    echo
    echo "| rtol | steps | rhs evals | instructions/run | µs/run | t_detect | peak F_r (rel) | robot impulse | object final speed | max stroke | energy residual | impacts |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
    for rtol in 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10; do
        atol=$(awk "BEGIN { printf \"%.0e\", $rtol / 1000 }")
        set_tol=(solver.rtol="$rtol" solver.atol="$atol")
        zero=$(count "$loop" 0 "$scene" "${set_tol[@]}")
        many=$(count "$loop" 50 "$scene" "${set_tol[@]}")
        # the row without its first cell, with the instructions put in after steps and rhs
        "$row" "$scene" "$rtol" | awk -v ins=$(((many - zero) / 50)) -F' \\| ' \
            'BEGIN { OFS = " | " } { $3 = $3 " | " ins; print }'
    done
done
