#!/bin/bash
# Skeleton extraction against CGAL's mean-curvature-flow skeletonizer, whole process
# against whole process: `sdm skeleton MESH -o S.json` and scripts/cgal_skeleton (read, extract with
# CGAL's defaults, write), run in turn, each the fastest of REPEAT runs, on every closed mesh of a
# folder.
# CGAL is no dependency of sdm: this builds the comparison program beside the repository, in
# ../cgal-bench-build, from Debian 12's libcgal-dev (apt install libcgal-dev).
#
# Usage: scripts/bench_cgal_skeleton.sh [SDM] [MESH_FOLDER] [REPEAT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sdm=${1:-$here/../build/sdm}
models=${2:-$here/../../shared/models/cgal}
repeat=${3:-11}
build=$here/../../cgal-bench-build
if [ ! -x "$build/cgal_skeleton" ]; then
  echo "building the CGAL comparison program in $build" >&2
  cmake -S "$here/cgal_skeleton" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j "$(nproc)" >/dev/null
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Wall-clock seconds of one run of a command (output discarded; bash's own clock, no process
# started to read it); "-" when it fails.
seconds() {
  local t0=$EPOCHREALTIME
  "$@" >/dev/null 2>&1 || { echo "-"; return; }
  echo "$t0 $EPOCHREALTIME" | awk '{print $2 - $1}'
}

# The two programs alternate, REPEAT runs each, and each keeps its fastest: on a shared VM whose
# speed drifts by tens of percent within a minute, timing one program's runs and then the other's
# measured the drift as much as the programs.
race() {
  local best_s=1e9 best_c=1e9 s c
  for _ in $(seq "$repeat"); do
    s=$(seconds "$sdm" skeleton "$1" -o "$tmp/s.json")
    c=$(seconds "$build/cgal_skeleton" "$1" "$tmp/c.obj")
    [ "$s" = "-" ] || [ "$c" = "-" ] && { echo "- -"; return; }
    best_s=$(echo "$s $best_s" | awk '{print ($1 < $2 ? $1 : $2)}')
    best_c=$(echo "$c $best_c" | awk '{print ($1 < $2 ? $1 : $2)}')
  done
  echo "$best_s $best_c"
}

echo "| mesh | vertices | sdm skeleton (s) | CGAL MCF (s) | CGAL / sdm |"
echo "|---|---|---|---|---|"
logsum=0
n=0
for mesh in "$models"/*.off "$models"/*.obj "$models"/*.ply; do
  [ -f "$mesh" ] || continue
  name=$(basename "$mesh")
  if ! "$build/cgal_skeleton" "$mesh" "$tmp/c.obj" >/dev/null 2>&1; then
    echo "| $name | - | - | - | not closed: skipped |"
    continue
  fi
  verts=$(awk 'NR == 1 && $1 == "OFF" {getline; print $1; exit} NR == 2 {print $1; exit}' "$mesh")
  read -r s c < <(race "$mesh")
  if [ "$s" = "-" ]; then
    echo "| $name | $verts | failed | - | - |"
    continue
  fi
  ratio=$(echo "$c $s" | awk '{printf "%.1f", $1 / $2}')
  logsum=$(echo "$logsum $c $s" | awk '{print $1 + log($2 / $3)}')
  n=$((n + 1))
  printf '| %s | %s | %.3f | %.3f | %s |\n' "$name" "$verts" "$s" "$c" "$ratio"
done
echo "$logsum $n" | awk '$2 > 0 {printf "\nGeometric mean of CGAL / sdm over %d meshes: %.1f\n", $2, exp($1 / $2)}'
