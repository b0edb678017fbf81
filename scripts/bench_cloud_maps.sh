#!/bin/sh
# Maps of point clouds (docs/BENCHMARKS.md, "Maps of point clouds"): clouds of N points sampled
# from closed meshes (no normals, Gaussian noise of 0.2 % of the diagonal per axis: sample_cloud.py),
# `sdm roundtrip CLOUD --reference MESH` at 1024 and level 3, and the decode judged against the
# source mesh by the independent checker (judge dist: RMS and Hausdorff as % of the diagonal).
# With CGAL_POISSON set to the benchmark-only Poisson program (scripts/cgal_poisson), its
# reconstruction of the same points is judged beside it. The skeleton check: `sdm skeleton` of the
# cloud against `sdm skeleton` of the source mesh (end nodes, branch nodes, cycles; the cycles
# should equal the source's genus).
# usage: scripts/bench_cloud_maps.sh BUILD_DIR OUT_DIR [MESH...]
set -eu
build=$1 out=$2
shift 2
judge=${JUDGE:-../judge-build/judge}
points=${POINTS:-50000}
here=$(dirname "$0")
mkdir -p "$out"
for mesh in "$@"; do
  name=$(basename "${mesh%.*}")
  "$build/sdm" convert "$mesh" -o "$out/$name.off" > /dev/null
  /usr/bin/python3 "$here/sample_cloud.py" "$out/$name.off" "$out/$name.xyz" --points "$points" --noise 0.002
  "$build/sdm" skeleton "$out/$name.off" -o "$out/$name.mesh.skeleton.json" --json > "$out/$name.mesh.skeleton.summary.json" 2>> "$out/$name.log"
  "$build/sdm" skeleton "$out/$name.xyz" -o "$out/$name.cloud.skeleton.json" --json > "$out/$name.cloud.skeleton.summary.json" 2>> "$out/$name.log"
  "$build/sdm" roundtrip "$out/$name.xyz" --reference "$out/$name.off" -o "$out/$name.decoded.ply" --json \
    > "$out/$name.roundtrip.json" 2> "$out/$name.log"
  "$judge" dist "$out/$name.off" "$out/$name.decoded.ply" --compact > "$out/$name.judge.json" 2>> "$out/$name.log"
  /usr/bin/python3 - "$name" "$out/$name.roundtrip.json" "$out/$name.judge.json" "$out/$name.mesh.skeleton.summary.json" \
    "$out/$name.cloud.skeleton.summary.json" <<'PY'
import json, sys
r, j = json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
m, c = json.load(open(sys.argv[4])), json.load(open(sys.argv[5]))
ends = lambda s: f"{s['end_nodes']} ends, {s['branch_nodes']} branches, {s['cycles']} cycles"
print(f"{sys.argv[1]}: skeleton of the cloud {ends(c)}; of the mesh {ends(m)}; "
      f"{'SAME' if all(c[k] == m[k] for k in ('end_nodes', 'branch_nodes', 'cycles')) else 'DIFFERENT'}")
print(f"{sys.argv[1]}: nodes {r['skeleton_nodes']}, segments {r['segments']}, gaps {r['gaps_filled']}, reached {100*r['reached']:.1f} %, "
      f"judge RMS {100*j['rms_rel']:.3f} %, Hausdorff {100*j['hausdorff_rel']:.2f} %, watertight {j['b_is_watertight']}, genus {j['b_genus']} "
      f"(source {j['a_genus']}); points->decoded RMS {100*r['points_rms']:.3f} %, max {100*r['points_max']:.2f} %; {r['seconds']:.1f} s")
PY
  if [ -n "${CGAL_POISSON:-}" ]; then
    "$CGAL_POISSON" "$out/$name.xyz" "$out/$name.poisson.off" > "$out/$name.poisson.log" 2>&1 || true
    if [ -s "$out/$name.poisson.off" ]; then
      "$judge" dist "$out/$name.off" "$out/$name.poisson.off" --compact > "$out/$name.poisson.judge.json" 2>> "$out/$name.log"
      /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(f'  Poisson: judge RMS {100*j[\"rms_rel\"]:.3f} %, Hausdorff {100*j[\"hausdorff_rel\"]:.2f} %, watertight {j[\"b_is_watertight\"]}, genus {j[\"b_genus\"]}')" "$out/$name.poisson.judge.json"
    fi
  fi
done
