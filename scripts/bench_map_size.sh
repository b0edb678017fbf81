#!/bin/bash
# Map size against error (docs/BENCHMARKS.md, "Map size against error, beside Draco"): for each
# mesh, `sdm roundtrip` at atlas sizes 256-2048 and each precision (the map written to a file and
# read back; bytes of that file), level 3; then Draco (Debian `draco`, benchmark only) at 8-14
# quantisation bits, measured with `sdm compare` (the same sampling as roundtrip). Prints a
# markdown table. Usage: scripts/bench_map_size.sh [SDM] MESH...
set -euo pipefail
SDM=${SDM:-build/sdm}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| mesh | setting | bytes | RMS (% of diagonal) | Hausdorff |"
echo "|---|---|---|---|---|"
for mesh in "$@"; do
  name=$(basename "${mesh%.*}")
  for size in 256 512 1024 2048; do
    for p in float half 10 8 7 6; do
      "$SDM" roundtrip "$mesh" --size $size --precision $p --json 2>/dev/null |
        /usr/bin/python3 -c "import json,sys; j=json.load(sys.stdin); print('| $name | sdm $size, $p | %d | %.4f | %.3f |' % (j['map_bytes'], 100*j['rms'], 100*j['hausdorff']))"
    done
  done
  if command -v draco_encoder >/dev/null; then
    "$SDM" convert "$mesh" -o "$tmp/in.ply" >/dev/null 2>&1
    for qp in 8 10 12 14; do
      draco_encoder -i "$tmp/in.ply" -o "$tmp/m.drc" -qp $qp -cl 10 >/dev/null
      draco_decoder -i "$tmp/m.drc" -o "$tmp/out.ply" >/dev/null
      bytes=$(stat -c %s "$tmp/m.drc")
      "$SDM" compare "$tmp/in.ply" "$tmp/out.ply" --json |
        /usr/bin/python3 -c "import json,sys; j=json.load(sys.stdin); print('| $name | Draco -qp $qp -cl 10 | $bytes | %.4f | %.3f |' % (100*j['rms'], 100*j['hausdorff']))"
    done
  fi
done
