#!/bin/sh
# The pictures of the shared scans in docs/BENCHMARKS.md ("Maps of point clouds"): for each scan,
# its points (one disk each), its skeleton over them, and the surface decoded from its map
# (`sdm roundtrip SCAN` at 1024, level 3).
# usage: scripts/cloud_pictures.sh BUILD_DIR OUT_DIR [SCAN...]   (default: the scans of ../shared)
set -eu
build=$1 out=$2
shift 2
scans=${*:-../shared/models/pointclouds/lamppost.pcd ../shared/models/pointclouds/woman.ply ../shared/models/pointclouds/tree_small.xyz}
mkdir -p "$out"
for scan in $scans; do
  name=$(basename "${scan%.*}")
  "$build/sdm" skeleton "$scan" -o "$out/$name.skeleton.json" > /dev/null
  "$build/sdm" render "$scan" --width 640 --height 640 --views 2 -o "$out/cloud_${name}_points.png" > /dev/null
  "$build/sdm" render "$scan" --skeleton "$out/$name.skeleton.json" --width 640 --height 640 -o "$out/cloud_${name}_skeleton.png" > /dev/null
  "$build/sdm" roundtrip "$scan" -o "$out/$name.decoded.ply" --json > "$out/$name.roundtrip.json"
  "$build/sdm" render "$out/$name.decoded.ply" --width 640 --height 640 --views 2 -o "$out/cloud_${name}_decoded.png" > /dev/null
  echo "$name: $out/cloud_${name}_points.png, _skeleton.png, _decoded.png"
done
