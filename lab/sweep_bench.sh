#!/usr/bin/env bash
# Sweep throughput and memory (a benchmark, not a test):
#   - runs per second on sweeps/design-space.toml (16,384 runs, rtol 1e-6) with 1 and 2 threads
#     (best of REPEAT, default 3, alternating, so a busy machine disturbs both alike),
#   - peak resident memory (/usr/bin/time -v) for 10^4 and 10^5 runs (the same axes, lhs, since
#     sobol stops at 65,536 points), which should be flat: rows are streamed to disk chunk by chunk.
# Usage: bash lab/sweep_bench.sh            (REPEAT=1 for a quick look)
#        CUSHION_BIN=target/pgo/release/cushion bash lab/sweep_bench.sh   (the profile-guided
#        build of scripts/build_pgo.sh)
# Results go to target/lab-out/sweep/ (git-ignored); the summary is printed and kept in results.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${CUSHION_BIN:-target/release/cushion}
[ -n "${CUSHION_BIN:-}" ] || cargo build --release -q
OUT=target/lab-out/sweep
REPEAT=${REPEAT:-3}
rm -rf "$OUT"; mkdir -p "$OUT"
TIME=/usr/bin/time
[ -x "$TIME" ] || { echo "needs GNU time: apt-get install -y time" >&2; exit 1; }

run() { # name threads sweepfile -> one line: runs wall cpu rss_kB
  local name=$1 threads=$2 file=$3
  rm -rf "$OUT/$name"
  $TIME -v "$BIN" sweep "$file" --out "$OUT/$name" --threads "$threads" --quiet 2> "$OUT/$name.time"
  python3 - "$OUT/$name" "$OUT/$name.time" <<'PY'
import json, sys
prov = json.load(open(sys.argv[1] + "/provenance.json"))
t = {}
for line in open(sys.argv[2]):
    k, _, v = line.strip().rpartition(": ")
    t[k] = v
cpu = float(t["User time (seconds)"]) + float(t["System time (seconds)"])
print(prov["runs_in_output"], prov["wall_seconds"], cpu, t["Maximum resident set size (kbytes)"])
PY
}

report() { # label threads "runs wall cpu rss" (best wall)
  python3 -c "
runs, wall, cpu, rss = '$3'.split(); runs=int(runs); wall=float(wall); cpu=float(cpu)
print(f'$1: threads $2, {runs} runs in {wall:.2f} s = {runs/wall:.0f} runs/s (CPU {cpu:.2f} s), peak RSS {int(rss)/1024:.1f} MiB')"
}

best() { sort -g -k2 | head -1; }

{
  echo "machine: $(nproc) cores, $(uname -m); load average $(cut -d' ' -f1-3 /proc/loadavg); cushion $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  : > "$OUT/t1.txt"; : > "$OUT/t2.txt"
  for i in $(seq "$REPEAT"); do
    run design-space-t1 1 sweeps/design-space.toml >> "$OUT/t1.txt"
    run design-space-t2 2 sweeps/design-space.toml >> "$OUT/t2.txt"
  done
  b1=$(best < "$OUT/t1.txt"); b2=$(best < "$OUT/t2.txt")
  report "design-space (best of $REPEAT)" 1 "$b1"
  report "design-space (best of $REPEAT)" 2 "$b2"
  python3 -c "print(f'speed-up 2 threads / 1 thread: {float(\"$b1\".split()[1]) / float(\"$b2\".split()[1]):.2f}x')"
  for n in 10000 100000; do
    sed -e 's/^mode = "sobol"/mode = "lhs"/' -e "s/^samples = .*/samples = $n/" \
        -e "s|^scene = \"|scene = \"$PWD/sweeps/|" -e "s/^name = .*/name = \"mem-$n\"/" \
        sweeps/design-space.toml > "$OUT/mem-$n.toml"
    report "memory, $n runs" 2 "$(run "mem-$n" 2 "$OUT/mem-$n.toml")"
  done
  echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$OUT/results.txt"
