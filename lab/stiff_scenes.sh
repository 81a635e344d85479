#!/usr/bin/env bash
# The stiff scenes under each method, in-process: wall time per run (median of ROUNDS rounds
# of N runs, `loop_scene`) and the run's counts (`cushion simulate --json`): evaluations,
# Jacobians, LU factorizations, switches. The scenes: the paper's hydraulic scene (dead time
# 70 ms) with steel end-stops (stops.stiffness = 1e11), with a steel contact
# (object.contact_stiffness = 1e10), and with a compressible liquid (hydraulic.bulk_modulus =
# 1.5e9, where dp5 and dop853 stop at their step limit and are left out). atol = rtol / 1000,
# the scene's ratio. SciPy's Radau, BDF and LSODA on the same scenes: lab/stiff_scenes_scipy.py.
#   bash lab/stiff_scenes.sh [ROUNDS] [N]       # defaults 5 and 20
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
n=${2:-20}
cargo build --release -q -p cushion-studies --bin loop_scene
cargo build --release -q --bin cushion
target=${CARGO_TARGET_DIR:-target}
loop=$target/release/loop_scene
scene=sweeps/scenes/paper-hydraulic-dt70.toml
printf '%-14s %-6s %-5s %10s %9s %9s %7s %8s  %s\n' scene method rtol 'µs/run' rhs_evals jacobians LUs switches status
for variant in "steel-stops stops.stiffness=1e11" "steel-contact object.contact_stiffness=1e10" \
    "compressible hydraulic.bulk_modulus=1.5e9"; do
    read -r name set <<<"$variant"
    for method in dp5 dop853 rodas auto; do
        [ "$name" = compressible ] && { [ "$method" = dp5 ] || [ "$method" = dop853 ]; } && continue
        for rtol in 1e-6 1e-7; do
            atol=$(python3 -c "print($rtol / 1000)")
            args=("$set" solver.method=$method solver.rtol=$rtol solver.atol=$atol)
            times=$(for _ in $(seq "$rounds"); do "$loop" "$n" "$scene" "${args[@]}" | awk '{print $1}'; done)
            median=$(printf '%s\n' $times | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
            sets=(); for a in "${args[@]}"; do sets+=(--set "$a"); done
            "$target/release/cushion" simulate "$scene" "${sets[@]}" --json | python3 -c "
import json, sys
d = json.load(sys.stdin); s = d['stats']
print('%-14s %-6s %-5s %10s %9d %9d %7d %8d  %s' % ('$name', '$method', '$rtol', '$median', s['rhs_evals'],
      s['jacobians'], s['lu_decompositions'], s['method_switches'], d['status']))"
        done
    done
done
