#!/usr/bin/env bash
# Whether two builds of `cushion` give the same numbers to the bit: the profile-guided build
# against the plain one (scripts/check_pgo.sh), or a refactored engine against a copy of the
# command built before the change. Compares, byte for byte:
#   - the summaries of scripts/pgo/training.toml (every method, rtol 1e-9 to 1e-4, end-stops up
#     to 1e11) and of the whole of sweeps/design-space.toml (16,384 runs);
#   - the five paper scenes under each adaptive method, their summaries and trajectories;
#   - the kept wide scenes of crates/cushion-model/tests/scenes, their summaries.
#   bash scripts/pgo/same_numbers.sh target/pgo/release/cushion target/release/cushion
set -euo pipefail
cd "$(dirname "$0")/../.."
[ $# -eq 2 ] || { echo "usage: same_numbers.sh CUSHION_A CUSHION_B" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

methods="auto dp5 dop853 rodas"
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
    "$bin" sweep sweeps/design-space.toml --out "$out/$side-design" --quiet
    for scene in sweeps/scenes/paper-*.toml; do
        name=$(basename "$scene" .toml)
        for m in $methods; do
            "$bin" simulate "$scene" --set solver.method=$m --json --csv "$out/$side-$name-$m.csv" \
                > "$out/$side-$name-$m.json"
        done
    done
    for scene in crates/cushion-model/tests/scenes/*.toml; do
        name=$(basename "$scene" .toml)
        "$bin" simulate "$scene" --json > "$out/$side-kept-$name.json" || true
    done
done
compare training.toml "$out/a-training/summary.csv" "$out/b-training/summary.csv"
compare design-space.toml "$out/a-design/summary.csv" "$out/b-design/summary.csv"
for scene in sweeps/scenes/paper-*.toml; do
    name=$(basename "$scene" .toml)
    for m in $methods; do
        compare "$name $m summary" "$out/a-$name-$m.json" "$out/b-$name-$m.json"
        compare "$name $m trajectory" "$out/a-$name-$m.csv" "$out/b-$name-$m.csv"
    done
done
for scene in crates/cushion-model/tests/scenes/*.toml; do
    name=$(basename "$scene" .toml)
    compare "kept scene $name" "$out/a-kept-$name.json" "$out/b-kept-$name.json"
done
[ $differ = 0 ] && echo "same numbers: $1 and $2 (512 + 16,384 sweep runs, 5 paper scenes x 4 methods with trajectories, 8 kept scenes)"
exit $differ
