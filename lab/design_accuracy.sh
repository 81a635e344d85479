#!/usr/bin/env bash
# Accuracy of the design-space sweep at its tolerance (rtol 1e-6) against the same 16,384 runs
# at rtol 1e-10: per summary field, the median, 99th percentile and largest error (relative;
# absolute in N s and m/s for the impulse and the object speed) and how many runs are off by
# more than 1e-4, and the mean evaluations per run. A benchmark, not a test:
# `bash lab/design_accuracy.sh`. Settings of the runs (the reference stays dp5 at rtol 1e-10)
# may follow as KEY=VALUE: `bash lab/design_accuracy.sh solver.method=dop853 solver.rtol=1e-7`.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
OUT=target/lab-out/accuracy
rm -rf "$OUT"; mkdir -p "$OUT"
sed -e 's/"solver.rtol" = 1e-6/"solver.rtol" = 1e-10/' \
    -e "s#scene = \"scenes/#scene = \"$PWD/sweeps/scenes/#" sweeps/design-space.toml > "$OUT/reference.toml"
sed -e "s#scene = \"scenes/#scene = \"$PWD/sweeps/scenes/#" sweeps/design-space.toml > "$OUT/run.toml"
for kv in "$@"; do
    key=${kv%%=*} value=${kv#*=}
    [[ $value =~ ^[-+0-9.eE]+$ ]] || value="\"$value\""
    sed -i -e "/^\"$key\" = /d" -e "s#^\[set\]\$#[set]\n\"$key\" = $value#" "$OUT/run.toml"
done
target/release/cushion sweep "$OUT/run.toml" --out "$OUT/run" --quiet
target/release/cushion sweep "$OUT/reference.toml" --out "$OUT/reference" --quiet
python3 - "$OUT/reference/summary.csv" "$OUT/run/summary.csv" <<'PY'
import csv, sys
ref, run = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
absolute = {"robot_impulse", "object_final_velocity"}
for k in ["peak_robot_force", "peak_contact_force", "max_stroke", "max_gas_pressure",
          "robot_impulse", "object_final_velocity"]:
    errs = []
    for r, x in zip(ref, run):
        if r[k] in ("", "null"):
            continue
        a, b = float(r[k]), float(x[k])
        errs.append(abs(a - b) / (1.0 if k in absolute else max(abs(a), 1e-300)))
    errs.sort()
    n = len(errs)
    print(f"{k:22s} median {errs[n // 2]:.1e}  p99 {errs[int(0.99 * n)]:.1e}  "
          f"max {errs[-1]:.1e}  runs > 1e-4: {sum(e > 1e-4 for e in errs)}")
print(f"evaluations per run (mean): {sum(int(r['stats_rhs_evals']) for r in run) / len(run):.0f}")
PY
