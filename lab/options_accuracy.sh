#!/usr/bin/env bash
# Accuracy over every option: a 3,000-run Latin hypercube over module, dead time, gas pressure,
# orifice, object mass, dry friction, plane friction, robot start, cavitation, brake and rtol
# (1e-4, 1e-6, 1e-8; atol 1e-9 as in the scenes), against the same runs at rtol 1e-11,
# atol 1e-14 (the reference sweep lists 1e-11 three times for the rtol axis, so that the
# hypercube draws the same points). Prints, per rtol, the median, 99th percentile and largest
# error of the object's final speed (m/s) and of the robot impulse (N s), with the worst run.
# A benchmark, not a test: `bash lab/options_accuracy.sh` (about a minute on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
OUT=target/lab-out/options
rm -rf "$OUT"; mkdir -p "$OUT"
sweep() { # rtol-axis-values [set-table-lines]
    cat <<EOF
name = "options"
scene = "$PWD/sweeps/scenes/paper-hydraulic-dt70.toml"
$2
[sampling]
mode = "lhs"
samples = 3000
seed = 11
[[axis]]
key = "module"
values = ["hydraulic", "bistable", "rigid"]
[[axis]]
key = "robot.dead_time"
range = [0.0, 0.1]
[[axis]]
key = "hydraulic.gas_pressure"
range = [300.0, 1e5]
scale = "log"
[[axis]]
key = "hydraulic.orifice_radius"
range = [0.002, 0.012]
[[axis]]
key = "object.mass"
range = [0.05, 1.0]
[[axis]]
key = "tool.dry_friction"
values = [0.0, 0.0, 0.3]
[[axis]]
key = "object.plane_friction"
values = [0.0, 0.0, 0.4]
[[axis]]
key = "robot.start"
values = ["cruising", "rest"]
[[axis]]
key = "hydraulic.cavitation"
values = [false, false, true]
[[axis]]
key = "robot.brake_deceleration"
range = [5.0, 30.0]
[[axis]]
key = "solver.rtol"
values = $1
EOF
}
sweep "[1e-6, 1e-8, 1e-4]" "" > "$OUT/run.toml"
sweep "[1e-11, 1e-11, 1e-11]" $'[set]\n"solver.atol" = 1e-14' > "$OUT/reference.toml"
target/release/cushion sweep "$OUT/run.toml" --out "$OUT/run" --quiet
target/release/cushion sweep "$OUT/reference.toml" --out "$OUT/reference" --quiet
python3 - "$OUT/reference/summary.csv" "$OUT/run/summary.csv" <<'PY'
import csv, sys
from collections import defaultdict
ref, run = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
axes = [k for k in run[0] if k not in ("run", "solver.rtol") and k in ref[0]][:10]
assert all(r[k] == x[k] for r, x in zip(ref, run) for k in axes), "not the same points"
errs = defaultdict(list)
for r, x in zip(ref, run):
    for k in ("object_final_velocity", "robot_impulse"):
        errs[(x["solver.rtol"], k)].append((abs(float(r[k]) - float(x[k])), int(x["run"])))
for (rtol, k), e in sorted(errs.items(), key=lambda kv: (-float(kv[0][0]), kv[0][1])):
    e.sort()
    n = len(e)
    print(f"rtol {rtol:6s} {k:22s} median {e[n // 2][0]:.1e}  p99 {e[int(0.99 * n)][0]:.1e}  "
          f"max {e[-1][0]:.1e} (run {e[-1][1]})")
PY
