#!/usr/bin/env bash
# Throughput of `sdm batch` (Dask, a local cluster of WORKERS processes) against the same work in a
# shell loop (one model after the other), on the 20 meshes of ../shared/models: `sdm stm` and
# `sdm encode` each (BENCHMARKS "Batches"). Prints models per minute for both.
# Usage: scripts/bench_batch.sh [SDM] [MODELS] [WORKERS]
set -euo pipefail
SDM=${1:-build/sdm}
MODELS=${2:-../shared/models}
WORKERS=${3:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
list="$out/models.txt"
for d in wild cgal humans spot; do
  find "$(realpath "$MODELS")/$d" -maxdepth 1 -type f \( -name '*.obj' -o -name '*.off' \) | sort
done >"$list"
n=$(wc -l <"$list")
start=$(date +%s.%N)
while read -r m; do
  name=$(basename "${m%.*}")
  "$SDM" stm "$m" -o "$out/loop-$name.layout.json" >/dev/null 2>&1
  "$SDM" encode "$m" -o "$out/loop-$name.exr" >/dev/null 2>&1
done <"$list"
loop=$(echo "$(date +%s.%N) - $start" | bc)
start=$(date +%s.%N)
"$SDM" batch "$list" -o "$out/batch" --do stm,encode --workers "$WORKERS" >/dev/null 2>"$out/batch.log" || true
batch=$(echo "$(date +%s.%N) - $start" | bc)
ok=$(grep -c ',ok,' "$out/batch/summary.csv" || true)
printf '| way | models | ok | seconds | models per minute |\n|---|---|---|---|---|\n'
printf '| shell loop | %d | %d | %.1f | %.1f |\n' "$n" "$n" "$loop" "$(echo "60 * $n / $loop" | bc -l)"
printf '| sdm batch, %d workers | %d | %d | %.1f | %.1f |\n' "$WORKERS" "$n" "$ok" "$batch" "$(echo "60 * $n / $batch" | bc -l)"
