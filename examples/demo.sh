#!/usr/bin/env bash
# The end-to-end demo on bundled data. Usage: examples/demo.sh SDM_BINARY OUT_DIR
# Each capability adds its step here; every result lands in OUT_DIR.
set -euo pipefail
SDM=${1:-build/sdm}
OUT=${2:-demo-out}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
SPOT="$HERE/data/spot/spot_triangulated.obj"

echo "== sdm demo: results in $OUT/"
echo "-- Spot, the textured example"
"$SDM" info "$SPOT" | tee "$OUT/spot-info.txt"
echo "== demo finished: see $OUT/"
