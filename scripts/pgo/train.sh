#!/usr/bin/env bash
# The training runs of the profile-guided build (scripts/build_pgo.sh): `cushion` at $1 runs
#   - sweeps/design-space.toml (16,384 runs at the engine's defaults: what most runs of a
#     user's sweep do),
#   - scripts/pgo/training.toml (512 runs: every method over rtol 1e-9 to 1e-4 and end-stop
#     stiffnesses 1e5 to 1e11, both modules, with and without the energy ledger),
#   - the paper scenes, one simulate each with its recorded trajectory (the recorder's path),
#     and the compressible liquid under rodas and auto.
# Outputs go to a scratch folder, deleted after.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

"$bin" sweep sweeps/design-space.toml --out "$out/design" --quiet
"$bin" sweep scripts/pgo/training.toml --out "$out/training" --quiet
for scene in sweeps/scenes/paper-*.toml; do
    "$bin" simulate "$scene" --csv "$out/run.csv" --json > /dev/null
done
for method in rodas auto; do
    "$bin" simulate sweeps/scenes/paper-hydraulic-dt70.toml --set hydraulic.bulk_modulus=1.5e9 \
        --set solver.method=$method --json > /dev/null
done
