#!/usr/bin/env bash
# The end-to-end demo on bundled data. Usage: examples/demo.sh SDM_BINARY OUT_DIR
# Every result lands in OUT_DIR; a summary table is printed at the end.
set -euo pipefail
SDM=$(realpath "${1:-build/sdm}")
OUT=${2:-demo-out}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
OUT=$(realpath "$OUT")
SPOT="$HERE/data/spot/spot_triangulated.obj"
SHAPES="ypsilon bottle donut triple-torus crossed-cylinders"
step() { echo; echo "== $*"; }

step "1. The paper's test shapes: generate, validate, preview (EGL, headless)"
for s in $SHAPES; do
  "$SDM" primitive "$s" -o "$OUT/$s.obj" 2>/dev/null
  "$SDM" info "$OUT/$s.obj" --json >"$OUT/$s.info.json"
  "$SDM" render "$OUT/$s.obj" -o "$OUT/$s.png" --width 512 --height 512 2>/dev/null >/dev/null
  python3 - "$OUT/$s.info.json" "$s" <<'PY' 2>/dev/null || echo "  $s: see $OUT/$s.info.json"
import json, sys
j = json.load(open(sys.argv[1]))
print(f"  {sys.argv[2]:18s} {j['vertices']:6d} vertices, genus {j['genus_per_part']}, findings: {len(j['findings'])}")
PY
done
"$SDM" info "$SPOT" | sed 's/^/  /'
"$SDM" render "$SPOT" -o "$OUT/spot.png" --width 512 --height 512 --azimuth 150 2>/dev/null >/dev/null

step "2. Skeletons (Laplacian contraction + connectivity surgery)"
for s in $SHAPES spot; do
  m="$OUT/$s.obj"; [ "$s" = spot ] && m="$SPOT"
  "$SDM" skeleton "$m" -o "$OUT/$s.skeleton.json" --obj "$OUT/$s.skeleton.obj" --json 2>/dev/null >"$OUT/$s.skeleton.summary.json"
  "$SDM" render "$m" --skeleton "$OUT/$s.skeleton.json" -o "$OUT/$s.skeleton.png" --width 512 --height 512 --no-texture 2>/dev/null >/dev/null
  python3 - "$OUT/$s.skeleton.summary.json" "$s" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"  {sys.argv[2]:18s} {j['nodes']:3d} nodes, {j['branch_nodes']} branch, {j['end_nodes']} ends, {j['cycles']} cycles")
PY
done

step "3. Skeleton texture map layout: checkerboard-ready uv and the packed atlas"
for s in $SHAPES spot; do
  m="$OUT/$s.obj"; [ "$s" = spot ] && m="$SPOT"
  "$SDM" stm "$m" --skeleton "$OUT/$s.skeleton.json" -o "$OUT/$s.layout.json" --uv-obj "$OUT/$s.stm-uv.obj" \
    --atlas-png "$OUT/$s.atlas.png" --json 2>/dev/null >"$OUT/$s.layout.summary.json"
  python3 - "$OUT/$s.layout.summary.json" "$s" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"  {sys.argv[2]:18s} {j['segments']:3d} segments, coverage {100*j['coverage']:.1f} %, L2 stretch {j['stretch']:.3f}")
PY
done

step "4. Texture remap: Spot's texture into its STM, Spot drawn from the STM with no uv (coordinates in shaders)"
"$SDM" remap "$SPOT" -o "$OUT/spot.stm.png" --size 2048 2>/dev/null | sed 's/^/  /'
"$SDM" render "$SPOT" --stm "$OUT/spot.stm.png" --layout "$OUT/spot.stm.json" --compare-uv --unlit --views 8 \
  --width 512 --height 512 -o "$OUT/spot.stm-vs-uv.png" 2>/dev/null | grep PSNR | sed 's/^/  8 views, own uv (left) vs STM (right) in spot.stm-vs-uv.png: /'
"$SDM" render "$SPOT" --stm "$OUT/spot.stm.png" --layout "$OUT/spot.stm.json" --azimuth 150 \
  --width 512 --height 512 -o "$OUT/spot.stm-view.png" 2>/dev/null >/dev/null

step "5. Skeleton displacement maps: encode (float EXR), decode at two levels, round-trip error"
for s in $SHAPES spot; do
  m="$OUT/$s.obj"; [ "$s" = spot ] && m="$SPOT"
  "$SDM" encode "$m" --layout "$OUT/$s.layout.json" -o "$OUT/$s.sdm.exr" --png "$OUT/$s.sdm.png" 2>/dev/null >/dev/null
  for l in 1 3; do
    "$SDM" decode "$OUT/$s.sdm.exr" --lod $l -o "$OUT/$s.decoded-lod$l.obj" 2>/dev/null >/dev/null
    "$SDM" render "$OUT/$s.decoded-lod$l.obj" -o "$OUT/$s.decoded-lod$l.png" --width 512 --height 512 --flat 2>/dev/null >/dev/null
  done
done
printf "  %-18s %10s %12s %9s %8s %7s\n" shape "RMS %diag" "Hausdorff %" "PSNR dB" faces closed
for s in $SHAPES spot; do
  m="$OUT/$s.obj"; [ "$s" = spot ] && m="$SPOT"
  "$SDM" roundtrip "$m" --size 1024 --lod 3 --json 2>/dev/null | python3 -c "
import json, sys
j = json.load(sys.stdin)
print(f\"  {'$s':18s} {100*j['rms']:10.4f} {100*j['hausdorff']:12.3f} {j['psnr']:9.1f} {j['faces']:8d} {str(j['closed']):>7s}\")"
done

echo
echo "== demo finished: every file is in $OUT/"
