#!/usr/bin/env bash
# Sweep throughput and memory (a benchmark, not a test):
#   - runs per second on sweeps/design-space.toml (16,384 runs, rtol 1e-6) with 1 and 2 threads,
#   - peak resident memory (/usr/bin/time -v) for 10^4 and 10^5 runs (the same axes, lhs),
#     which should be flat: rows are streamed to disk chunk by chunk.
# Usage: bash bench/sweep_bench.sh [--quick]   (--quick: 2,048-run shards instead of the full sweep)
# Results go to bench/out/sweep/ (git-ignored); a summary is printed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
BIN=target/release/cushion
OUT=bench/out/sweep
rm -rf "$OUT"; mkdir -p "$OUT"
TIME=/usr/bin/time
[ -x "$TIME" ] || { echo "needs GNU time: apt-get install -y time" >&2; exit 1; }

shard=()
[ "${1:-}" = "--quick" ] && shard=(--shard 1/8)

measure() { # name threads sweepfile -> prints "runs seconds runs/s maxrss_kB"
  local name=$1 threads=$2 file=$3
  $TIME -v "$BIN" sweep "$file" --out "$OUT/$name" --threads "$threads" --quiet "${shard[@]}" 2> "$OUT/$name.time"
  local runs secs rss
  runs=$(python3 -c "import json;print(json.load(open('$OUT/$name/provenance.json'))['runs_in_output'])")
  secs=$(python3 -c "import json;print(json.load(open('$OUT/$name/provenance.json'))['wall_seconds'])")
  rss=$(grep "Maximum resident set size" "$OUT/$name.time" | awk '{print $NF}')
  python3 -c "print(f'$name: threads $threads, {int($runs)} runs in {float($secs):.2f} s = {int($runs)/float($secs):.0f} runs/s, peak RSS {int($rss)/1024:.1f} MiB')"
}

{
  echo "machine: $(nproc) cores, $(uname -m); cushion $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  measure design-space-t1 1 sweeps/design-space.toml
  measure design-space-t2 2 sweeps/design-space.toml
  # 10^4 and 10^5 runs: the design-space axes with lhs (sobol stops at 65,536 points).
  for n in 10000 100000; do
    sed -e 's/^mode = "sobol"/mode = "lhs"/' -e "s/^samples = .*/samples = $n/" \
        -e "s|^scene = \"|scene = \"$PWD/sweeps/|" -e "s/^name = .*/name = \"mem-$n\"/" \
        sweeps/design-space.toml > "$OUT/mem-$n.toml"
    shard=()
    measure "mem-$n" 2 "$OUT/mem-$n.toml"
  done
} | tee "$OUT/results.txt"
