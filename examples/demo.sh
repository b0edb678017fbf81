#!/usr/bin/env bash
# The end-to-end demo on bundled data. Usage: examples/demo.sh SDM_BINARY OUT_DIR
# Every result lands in OUT_DIR; each stage prints a short summary. Needs only bash and coreutils.
set -euo pipefail
SDM=$(realpath "${1:-build/sdm}")
OUT=${2:-demo-out}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
OUT=$(realpath "$OUT")
SPOT="$HERE/data/spot/spot_triangulated.obj"
SHAPES="ypsilon bottle donut triple-torus crossed-cylinders"
MODELS="$SHAPES spot"
step() { echo; echo "== $*"; }
mesh_of() { if [ "$1" = spot ]; then echo "$SPOT"; else echo "$OUT/$1.obj"; fi; }
quiet() { "$@" 2>/dev/null >/dev/null; }

step "1. The paper's test shapes: generate, validate, preview (GL through EGL, headless)"
for s in $SHAPES; do
  quiet "$SDM" primitive "$s" -o "$OUT/$s.obj"
  "$SDM" info "$OUT/$s.obj" >"$OUT/$s.info.txt"
  awk -v n="$s" '/^  vertices/{v=$2} /genus per part/{g=$4} /pipeline/{p=$2}
    END{printf "  %-18s %6d vertices, genus %s, pipeline %s\n", n, v, g, p}' "$OUT/$s.info.txt"
  quiet "$SDM" render "$OUT/$s.obj" -o "$OUT/$s.png" --width 512 --height 512
done
"$SDM" info "$SPOT" >"$OUT/spot.info.txt"
awk '/^  vertices/{v=$2} /genus per part/{g=$4} /^  uv/{u=$2} END{printf "  %-18s %6d vertices, genus %s, uv %s\n", "spot", v, g, u}' "$OUT/spot.info.txt"
quiet "$SDM" render "$SPOT" -o "$OUT/spot.png" --width 512 --height 512 --azimuth 150

step "2. Skeletons (Laplacian contraction + connectivity surgery), drawn over the surface"
for s in $MODELS; do
  m=$(mesh_of "$s")
  "$SDM" skeleton "$m" -o "$OUT/$s.skeleton.json" --obj "$OUT/$s.skeleton.obj" 2>/dev/null >"$OUT/$s.skeleton.txt"
  awk -v n="$s" '{k[$1]=$2} END{printf "  %-18s %3d nodes, %d branch, %d ends, %d cycles, %.3f s\n", n, k["nodes"],
    k["branch_nodes"], k["end_nodes"], k["cycles"], k["contraction_seconds"]+k["surgery_seconds"]+k["refinement_seconds"]}' \
    "$OUT/$s.skeleton.txt"
  quiet "$SDM" render "$m" --skeleton "$OUT/$s.skeleton.json" -o "$OUT/$s.skeleton.png" --width 512 --height 512 --no-texture
done

step "3. Skeleton texture map layout: checkerboard views (*.checker.png), packed atlases (*.atlas.png), STM uv (*.stm-uv.obj)"
for s in $MODELS; do
  m=$(mesh_of "$s")
  "$SDM" stm "$m" --skeleton "$OUT/$s.skeleton.json" -o "$OUT/$s.layout.json" --uv-obj "$OUT/$s.stm-uv.obj" \
    --atlas-png "$OUT/$s.atlas.png" 2>/dev/null >"$OUT/$s.layout.txt"
  awk -v n="$s" '/^  segments/{s=$2} /^  coverage/{c=$2} /L2 stretch/{t=$3}
    END{printf "  %-18s %3d segments, coverage %.1f %%, L2 stretch %.3f\n", n, s, 100*c, t}' "$OUT/$s.layout.txt"
  quiet "$SDM" render "$m" --layout "$OUT/$s.layout.json" --checker -o "$OUT/$s.checker.png" --width 512 --height 512 --azimuth 150
done

step "4. Texture remap: Spot's texture into its STM, Spot drawn from the STM with no uv (coordinates in shaders)"
"$SDM" remap "$SPOT" -o "$OUT/spot.stm.png" --size 2048 2>/dev/null | head -1 | sed 's/^/  /'
"$SDM" render "$SPOT" --stm "$OUT/spot.stm.png" --layout "$OUT/spot.stm.json" --compare-uv --unlit --views 8 \
  --width 512 --height 512 -o "$OUT/spot.stm-vs-uv.png" 2>/dev/null | grep PSNR | sed 's/^/  8 views, own uv vs STM (spot.stm-vs-uv.png): /'
quiet "$SDM" render "$SPOT" --stm "$OUT/spot.stm.png" --layout "$OUT/spot.stm.json" --azimuth 150 \
  --width 512 --height 512 -o "$OUT/spot.stm-view.png"

step "5. Skeleton displacement maps: encode (OpenEXR, 10-bit residuals), decode at levels 1 and 3, round-trip error"
for s in $MODELS; do
  m=$(mesh_of "$s")
  quiet "$SDM" encode "$m" --layout "$OUT/$s.layout.json" -o "$OUT/$s.sdm.exr" --png "$OUT/$s.sdm.png"
  for l in 1 3; do
    quiet "$SDM" decode "$OUT/$s.sdm.exr" --lod $l -o "$OUT/$s.decoded-lod$l.obj"
    quiet "$SDM" render "$OUT/$s.decoded-lod$l.obj" -o "$OUT/$s.decoded-lod$l.png" --width 512 --height 512 --flat
  done
done
for s in $MODELS; do
  "$SDM" roundtrip "$(mesh_of "$s")" --size 1024 --lod 3 2>/dev/null | sed "s|^.* at 1024|  $s: 1024 map|"
done

step "6. Texture transfer: Spot's texture onto a remeshed Spot, a reposed Spot, a Spot with thicker legs and a long-legged Spot"
# The reposed, thick-legged and long-legged Spots are made here by smooth deformations of Spot's
# vertices (awk; the same triangles): the head turned 30 degrees about the vertical through the
# neck with a weight ramping from 0 behind the neck to 1 at the head (a one-joint skinning); the
# legs widened up to 1.35 times about their own axes with a weight ramping from the belly to the
# hooves; the legs 1.6 times longer and the body and neck 1.3 times longer. All keep Spot's
# branching. The remesh is recognised as Spot's shape (the skeleton is carried over), the others as
# Spot in another pose or proportion (Spot's skeleton is bent onto them): the skeletons extracted
# from them differ from Spot's by the tessellation (8 or 10 ends), so they are not used.
"$SDM" remesh "$SPOT" -o "$OUT/spot-remeshed.obj" --factor 1.2 2>/dev/null | sed 's/^/  /'
# move KIND: the deformation of one point (x, y, z), in awk.
MOVE='function ramp(t) { t = t < 0 ? 0 : (t > 1 ? 1 : t); return t * t * (3 - 2 * t) }
  function move(kind,   w, a, dx, dz, cx, cz, s) {
    if (kind == "reposed") {
      w = ramp(-z / 0.3) * ramp(y / 0.3); a = w * 30 * 3.14159265 / 180
      dx = x; dz = z + 0.05; x = dx * cos(a) + dz * sin(a); z = -dx * sin(a) + dz * cos(a) - 0.05
    } else if (kind == "thick-legs") {
      w = ramp((-0.3 - y) / 0.2); cx = x < 0 ? -0.21 : 0.21; cz = z < 0.4 ? 0.05 : 0.74
      s = 1 + 0.35 * w; x = cx + s * (x - cx); z = cz + s * (z - cz)
    } else {
      if (y < -0.3) y = -0.3 + 1.6 * (y + 0.3)
      z = z > -0.3 ? 1.3 * z : z - 0.09
    } }'
for t in reposed thick-legs long-legs; do
  awk -v kind="$t" "$MOVE"'
    /^(mtllib|usemtl)/ { next }
    $1 == "v" { x = $2; y = $3; z = $4; move(kind); printf "v %.6f %.6f %.6f\n", x, y, z; next }
    { print }' "$SPOT" >"$OUT/spot-$t.obj"
done
for t in remeshed reposed thick-legs long-legs; do
  if "$SDM" transfer --source "$SPOT" --target "$OUT/spot-$t.obj" -o "$OUT/spot-$t-transferred.obj" --size 1024 \
    >"$OUT/spot-$t-transferred.txt" 2>"$OUT/spot-$t-transferred.log"; then
    printf "  %-11s %s\n" "$t" "$(grep -m1 -o 'the target is .*' "$OUT/spot-$t-transferred.txt" || grep -m1 confidence "$OUT/spot-$t-transferred.txt" | sed 's/^ *//')"
    echo "              preview spot-$t-transferred_preview.png"
  else
    echo "  $t: refused: $(tail -1 "$OUT/spot-$t-transferred.log" | sed 's/^sdm transfer: error: //')"
  fi
done

step "7. Texture transfer between bodies (shared FAUST and TOSCA models): FAUST tr_reg_007 onto tr_reg_024, the gorilla onto the man"
# The models are not bundled: they are read from ../shared/models/humans beside the repository
# (SDM_HUMANS overrides), and the step is skipped without them. Each source is textured by sdm
# itself: its STM uv (`sdm stm --uv-obj`) and the atlas drawing (`--atlas-png`, every skeleton
# segment in its own colour) as texture, so the preview shows where each body part lands.
HUMANS=${SDM_HUMANS:-$(cd "$HERE/.." && pwd)/../shared/models/humans}
# bodies NAME SOURCE TARGET: textured SOURCE onto TARGET, with preview, correspondence and vertex colours.
bodies() {
  local name=$1 src=$2 tgt=$3
  quiet "$SDM" stm "$HUMANS/$src.off" -o "$OUT/$src.stm.json" --uv-obj "$OUT/$src-textured.obj" --atlas-png "$OUT/$src-textured.png"
  if "$SDM" transfer --source "$OUT/$src-textured.obj" --target "$HUMANS/$tgt.off" -o "$OUT/$name.obj" --size 1024 \
    --correspondence "$OUT/$name.correspondence.txt" --vertex-colors "$OUT/$name.colors.ply" --json \
    >"$OUT/$name.json" 2>"$OUT/$name.log"; then
    awk -v n="$src -> $tgt" -v p="$name" '/"target_skeleton"/{gsub(/[",]/, "", $2); t=$2} /"fit_rms"/{r=$2} /"fit_p99"/{q=$2}
      END{printf "  %-26s %s, fit %.2f %% RMS, %.2f %% p99; %s_preview.png, %s.correspondence.txt, %s.colors.ply\n",
        n, t, 100*r, 100*q, p, p, p}' "$OUT/$name.json"
  else
    echo "  $src -> $tgt: refused: $(tail -1 "$OUT/$name.log" | sed 's/^sdm transfer: error: //')"
  fi
}
if [ -d "$HUMANS" ]; then
  bodies faust-007-to-024 tr_reg_007 tr_reg_024
  bodies gorilla-to-man 8_gorilla_01 8_man_02
else
  echo "  skipped: no $HUMANS (FAUST and TOSCA models are not bundled with the repository)"
fi

echo
echo "== demo finished: every file is in $OUT/"
