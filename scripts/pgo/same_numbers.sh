#!/usr/bin/env bash
# Whether two builds of `cushion` give the same numbers to the bit: the profile-guided build
# (scripts/build_pgo.sh) against the plain one. Compares, byte for byte, the summaries of
# scripts/pgo/training.toml (every method, rtol 1e-9 to 1e-4, end-stops up to 1e11), of a
# shard of sweeps/design-space.toml and, with their trajectories, of the paper scenes.
#   bash scripts/pgo/same_numbers.sh target/pgo/release/cushion target/release/cushion
set -euo pipefail
cd "$(dirname "$0")/../.."
[ $# -eq 2 ] || { echo "usage: same_numbers.sh CUSHION_A CUSHION_B" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

differ=0
compare() { # label file_a file_b
    if ! cmp -s "$2" "$3"; then
        echo "differ: $1" >&2
        differ=1
    fi
}
for side in a b; do
    bin=$1; [ $side = b ] && bin=$2
    "$bin" sweep scripts/pgo/training.toml --out "$out/$side-training" --quiet
    "$bin" sweep sweeps/design-space.toml --shard 3/16 --out "$out/$side-design" --quiet
    for scene in sweeps/scenes/paper-*.toml; do
        name=$(basename "$scene" .toml)
        "$bin" simulate "$scene" --json --csv "$out/$side-$name.csv" > "$out/$side-$name.json"
    done
done
compare training.toml "$out/a-training/summary.csv" "$out/b-training/summary.csv"
compare "design-space shard 3/16" "$out/a-design/summary.csv" "$out/b-design/summary.csv"
for scene in sweeps/scenes/paper-*.toml; do
    name=$(basename "$scene" .toml)
    compare "$name summary" "$out/a-$name.json" "$out/b-$name.json"
    compare "$name trajectory" "$out/a-$name.csv" "$out/b-$name.csv"
done
[ $differ = 0 ] && echo "same numbers: $1 and $2 (512 + 1,024 sweep runs, 5 paper scenes with trajectories)"
exit $differ
