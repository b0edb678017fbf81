#!/bin/bash
# Every real mesh through repair, the STM and the round trip (docs/BENCHMARKS.md, "Mesh repair"
# and "Round trips of every real mesh"): per mesh, the repairs `sdm info` names, `sdm stm`'s
# segments and coverage, and `sdm roundtrip --size 1024 --lod 3` (RMS and Hausdorff in % of the
# diagonal, the share of the input carried); with JUDGE set to the binary of ../shared/judge, also
# the judge's distance between the input and the decoded mesh, measured from outside (an OBJ with
# polygons is given to the judge fan-triangulated, as sdm's reader triangulates convex polygons:
# the judge's own triangulation of Suzanne's non-planar quads lies 0.18 % RMS from either fan,
# which is the input's ambiguity, not an error of the map). Prints a
# markdown table. Usage: scripts/bench_real_meshes.sh [MESH...] (default: every mesh of ../shared/models).
set -euo pipefail
SDM=${SDM:-build/sdm}
JUDGE=${JUDGE:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [ $# -eq 0 ]; then
  set -- ../shared/models/wild/*.obj ../shared/models/cgal/*.off ../shared/models/humans/*.off ../shared/models/spot/*.obj
fi
echo "| mesh | repairs | segments | coverage | RMS (%) | Hausdorff (%) | carried | judge RMS (%) | judge Hausdorff (%) |"
echo "|---|---|---|---|---|---|---|---|---|"
for mesh in "$@"; do
  name=$(basename "${mesh%.*}")
  repairs=$("$SDM" info "$mesh" --json 2>/dev/null | /usr/bin/python3 -c "
import json,sys; j=json.load(sys.stdin)
print('; '.join('%d %s' % (s['count'], s['kind'].split(' (')[0]) for s in j['repair']['steps']) or 'none')")
  stm=$("$SDM" stm "$mesh" -o "$tmp/l.json" --json 2>/dev/null | /usr/bin/python3 -c "
import json,sys; j=json.load(sys.stdin); print('%d | %.3f' % (j['segments'], j['coverage']))") || stm="refused | -"
  rt=$("$SDM" roundtrip "$mesh" --size 1024 --lod 3 -o "$tmp/d.obj" --json 2>/dev/null | /usr/bin/python3 -c "
import json,sys; j=json.load(sys.stdin); print('%.4f | %.3f | %.3f' % (100*j['rms'], 100*j['hausdorff'], j['carried']))") || rt="refused | - | -"
  judged="- | -"
  if [ -n "$JUDGE" ] && [ -f "$tmp/d.obj" ]; then
    reference=$mesh
    if [ "${mesh##*.}" = obj ]; then
      /usr/bin/python3 -c "
import sys
out = []
for line in open(sys.argv[1], errors='replace'):
    t = line.split()
    if t and t[0] == 'f' and len(t) > 4:
        out += ['f %s %s %s' % (t[1], t[i], t[i + 1]) for i in range(2, len(t) - 1)]
    else:
        out.append(line.rstrip('\\n'))
open(sys.argv[2], 'w').write('\\n'.join(out) + '\\n')" "$mesh" "$tmp/ref.obj"
      reference=$tmp/ref.obj
    fi
    judged=$("$JUDGE" dist "$reference" "$tmp/d.obj" --compact 2>/dev/null | /usr/bin/python3 -c "
import json,sys; j=json.load(sys.stdin); print('%.4f | %.3f' % (100*j['rms_rel'], 100*j['hausdorff_rel']))") || judged="failed | -"
  fi
  rm -f "$tmp/d.obj"
  echo "| $name | $repairs | $stm | $rt | $judged |"
done
